"""The gdb-like console of ``melfa debug``: one command per line in, plain text out.

`Console.execute(line)` runs one command on a `Debugger` and writes what happened to `out`;
``melfa debug`` (in `melfa.cli.debug_commands`) feeds it lines from the terminal or from
stdin. After every stop it writes ``stopped at line N: <source>``; at the end ``finished``
or the run-time error with its number and line. Commands (short forms in brackets):

    break N | break *LABEL [b]   delete [N] [d]     run [r]        continue [c]
    step [s]     next [n]        finish            until N        print EXPR [p]
    info vars | info breakpoints [i]   where [bt]  input N=V      speed real|xN|instant
    preflight    help [h]        quit [q]
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TextIO

from melfa.sim.debug.cell import Cell
from melfa.sim.debug.engine import (
    BUSY_STATEMENTS,
    DebugError,
    Debugger,
    RunState,
    Speed,
    Stop,
    StopReason,
)
from melfa.sim.debug.preflight import preflight, report_text
from melfa.sim.debug.view import VarKind, VarView
from melfa.sim.interp.io import parse_input

HELP = """commands:
  break N          stop before line N of the file      break *LABEL   stop at a label
  delete N         remove breakpoint N (no N: all)     info breakpoints
  run              start from the first line           continue       go on to the next stop
  step             one statement, into GOSUB           next           one statement, over GOSUB
  finish           until the subroutine returns        until N        run to line N
  print EXPR       a value (print M1, print P1.X)      info vars      every variable
  where            the GOSUB stack                     input N=V      set input M_IN(N) to V
  speed real|xN|instant                                preflight      the pre-flight report
  quit
"""

_ALIASES = {
    "b": "break",
    "d": "delete",
    "r": "run",
    "c": "continue",
    "cont": "continue",
    "s": "step",
    "n": "next",
    "fin": "finish",
    "u": "until",
    "advance": "until",
    "p": "print",
    "i": "info",
    "bt": "where",
    "backtrace": "where",
    "h": "help",
    "q": "quit",
    "exit": "quit",
}


@dataclass
class Console:
    """Runs console commands on `debugger`; `idle()` is called between polls while a run
    goes on in real time (the CLI sleeps a tick; at instant speed it is never needed)."""

    debugger: Debugger
    out: TextIO
    idle: Callable[[], None] = lambda: None
    cell: Cell | None = None
    """The cell `preflight` checks against (None: the default table at Z = 0)."""
    failed: bool = False
    """Whether the last run ended with a run-time error (the exit code says so)."""

    def execute(self, line: str) -> bool:
        """Run one command line; False when the user asked to quit."""
        words = line.strip().split(None, 1)
        if not words:
            return True
        name = _ALIASES.get(words[0].lower(), words[0].lower())
        arg = words[1].strip() if len(words) > 1 else ""
        if name == "quit":
            return False
        handler = _COMMANDS.get(name)
        if handler is None:
            self._say(f"error: unknown command {words[0]!r} (help lists the commands)")
            return True
        try:
            handler(self, arg)
        except DebugError as exc:
            self._say(f"error: {exc}")
        return True

    # ------------------------------------------------------------------ commands
    def _break(self, arg: str) -> None:
        d = self.debugger
        if not arg:
            raise DebugError("break where? (break 12, or break *LABEL)")
        bp = d.break_label(arg) if arg.startswith("*") else d.break_line(_number(arg, "break"))
        self._say(f"breakpoint {bp.id} at line {bp.line}: {d.source_at(bp.line)}")

    def _delete(self, arg: str) -> None:
        if not arg:
            self.debugger.clear_breakpoints()
            self._say("deleted all breakpoints")
            return
        number = _number(arg, "delete")
        self.debugger.delete(number)
        self._say(f"deleted breakpoint {number}")

    def _run(self, arg: str) -> None:
        self.debugger.run()
        self._wait_for_stop()

    def _continue(self, arg: str) -> None:
        self.debugger.continue_()
        self._wait_for_stop()

    def _step(self, arg: str) -> None:
        self.debugger.step()
        self._wait_for_stop()

    def _next(self, arg: str) -> None:
        self.debugger.step_over()
        self._wait_for_stop()

    def _finish(self, arg: str) -> None:
        self.debugger.step_out()
        self._wait_for_stop()

    def _until(self, arg: str) -> None:
        self.debugger.run_to(_number(arg, "until"))
        self._wait_for_stop()

    def _print(self, arg: str) -> None:
        self._say(self.debugger.evaluate(arg))

    def _info(self, arg: str) -> None:
        what = arg.lower()
        if what in ("vars", "variables", "locals", "v"):
            self._info_vars()
        elif what in ("breakpoints", "break", "b"):
            bps = self.debugger.breakpoints
            if not bps:
                self._say("no breakpoints")
            for bp in bps:
                label = f" (*{bp.label})" if bp.label else ""
                self._say(f"{bp.id}: line {bp.line}{label}: {self.debugger.source_at(bp.line)}")
        else:
            raise DebugError("info what? (info vars, info breakpoints)")

    def _info_vars(self) -> None:
        rows = self.debugger.variables()
        if not rows:
            self._say("no variables")
        kind: VarKind | None = None
        for row in rows:
            if row.kind is not kind:
                kind = row.kind
                self._say(f"{_HEADINGS[kind]}:")
            self._say(_var_line(row, "  "))
            for element in row.elements:
                self._say(_var_line(element, "    "))

    def _where(self, arg: str) -> None:
        frames = self.debugger.where()
        if not frames or self.debugger.state is RunState.IDLE:
            self._say("the program is not running")
            return
        for i, f in enumerate(frames):
            how = f" (interrupt, DEF ACT {f.interrupt})" if f.interrupt is not None else ""
            self._say(f"#{i} line {f.location.line}: {f.location.source}{how}")

    def _input(self, arg: str) -> None:
        try:
            bit, value = parse_input(arg)
        except ValueError as exc:
            raise DebugError(str(exc)) from None
        self.debugger.set_input(bit, value)
        self._say(f"M_IN({bit}) = {value}")

    def _speed(self, arg: str) -> None:
        self.debugger.set_speed(Speed.parse(arg or "?"))
        self._say(f"speed {self.debugger.speed.text}")

    def _preflight(self, arg: str) -> None:
        d = self.debugger
        report = preflight(
            d.text, d.points, cell=self.cell, inputs=d.io.inputs().items(), max_time=d.max_time
        )
        self.out.write(report_text(report))

    def _help(self, arg: str) -> None:
        self.out.write(HELP)

    # ------------------------------------------------------------------ stops
    def _wait_for_stop(self) -> None:
        d = self.debugger
        while True:
            stop = d.poll()
            if stop is not None:
                self._report(stop)
                return
            if d.state is not RunState.RUNNING:
                return
            if d.speed.factor is None and d.waiting:
                loc = d.location
                where = f"line {loc.line}: {loc.source}" if loc else "a WAIT"
                self._say(f"waiting at {where} (set an input with: input N=V, then continue)")
                return
            self.idle()

    def _report(self, stop: Stop) -> None:
        d = self.debugger
        loc = stop.location
        if stop.reason is StopReason.END:
            self.failed = False
            self._say(f"finished at line {loc.line} after {d.time:.3f} s (simulated)")
            return
        if stop.reason is StopReason.ERROR and stop.error is not None:
            self.failed = True
            self._say(f"error at line {loc.line}: {stop.error.text}")
            self._say(f"  {loc.line} | {loc.source}")
            return
        if stop.reason is StopReason.BREAKPOINT:
            self._say(f"breakpoint {stop.breakpoint}")
        elif stop.reason is StopReason.HLT:
            self._say("paused by HLT")
        elif stop.reason is StopReason.TIME_LIMIT:
            self._say(f"stopped after {d.max_time:g} s of simulated time (--max-time)")
        elif stop.reason is StopReason.BUSY:
            self._say(
                f"stopped: {BUSY_STATEMENTS:,} statements ran without a move, DLY or WAIT "
                "(an endless loop?)"
            )
        self._say(f"stopped at line {loc.line}: {loc.source}")

    def _say(self, text: str) -> None:
        self.out.write(text + "\n")


def _number(text: str, command: str) -> int:
    try:
        return int(text.strip())
    except ValueError:
        raise DebugError(f"{command} needs a line number, not {text.strip()!r}") from None


def _var_line(row: VarView, indent: str) -> str:
    mark = "   (changed)" if row.changed else ""
    return f"{indent}{row.name} = {row.value}{mark}"


_HEADINGS = {
    VarKind.NUMBER: "numbers",
    VarKind.STRING: "strings",
    VarKind.POSITION: "positions",
    VarKind.JOINT: "joints",
    VarKind.ARRAY: "arrays",
    VarKind.INPUT: "inputs on",
    VarKind.OUTPUT: "outputs on",
    VarKind.ROBOT: "robot",
}

_COMMANDS: dict[str, Callable[[Console, str], None]] = {
    "break": Console._break,
    "delete": Console._delete,
    "run": Console._run,
    "continue": Console._continue,
    "step": Console._step,
    "next": Console._next,
    "finish": Console._finish,
    "until": Console._until,
    "print": Console._print,
    "info": Console._info,
    "where": Console._where,
    "input": Console._input,
    "speed": Console._speed,
    "preflight": Console._preflight,
    "help": Console._help,
}
