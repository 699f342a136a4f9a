"""The synchronous robot client: one session with one controller.

Shaped like h11's basic client: a thin loop that writes requests and reads replies, every
wire decision left to `melfa.protocol`. Unlike the thesis (protocol.md §4.2), which opened a new
connection and re-ran OPEN/CNTLON/RSTPRG/PRGLOAD/SRVON for every command, the session opens
once (``OPEN=<client name>``) and takes the operation rights (``CNTLON``) the first time an
operation needs them [DOC S1 §5.1 `*` commands], keeping both until `close`.

Threads: one worker thread uses the client (the service runs it that way); any other thread
may call `stop` at any time. See `stop` and `melfa.robot.channel` for how STOP overtakes a
request in flight.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Final

from melfa.link import Link, LinkError, LinkSettings
from melfa.protocol import (
    EDIT_SLOT,
    HANDS,
    OVERRIDE_PERCENT,
    DState,
    ErrorCode,
    ErrorStatus,
    HandStatus,
    Jog,
    JogMode,
    LocalProtocolError,
    Ok,
    OpenBanner,
    Position,
    Refused,
    RemoteProtocolError,
    Reply,
    Request,
    State,
    error_code,
    error_level,
    error_text,
    span_text,
)
from melfa.protocol.answers import RunStatus
from melfa.protocol.commands import needs_rights
from melfa.protocol.error_table import (
    BUSY,
    JOG_NOT_ACCEPTED,
    NO_RIGHTS,
    PROGRAM_NOT_FOUND,
)
from melfa.robot import edit
from melfa.robot.channel import Channel
from melfa.robot.edit import Progress, UploadReport
from melfa.robot.errors import ControllerError, RobotError, Stopped
from melfa.robot.settings import HandMethod, JogMethod, RobotSettings
from melfa.robot.status import Alarm, ControllerStatus
from melfa.robot.upload import sendable

if TYPE_CHECKING:
    from melfa.lang.plan import UploadPlan

JOG_JOINT_VARIABLE: Final = "JMJOG"
"""Joint variable the step jog assigns (≤ 8 characters, L4300; leading J = joint type)."""

COMMAND_SHOWN: Final = 80
"""A refused command is quoted in the error up to this many characters."""


class Robot:
    """A session with one controller over one `Link`.

    >>> from melfa.sim import open_sim_link
    >>> with Robot(open_sim_link()) as robot:
    ...     robot.override(50)
    ...     robot.joints().values("J1", "J2")
    50
    (0.0, 0.0)
    """

    def __init__(self, link: Link, settings: RobotSettings | None = None) -> None:
        self.link = link
        self.settings = settings or RobotSettings()
        self.channel = Channel(link, self.settings.robot)
        self.banner: OpenBanner | None = None
        self.alarm = False
        """True while the last reply was ``Qok``/``Qer`` (an alarm is active)."""
        self.pdir_hints: dict[str, int] = {}
        self.handshaken = False
        """The PRTVER handshakes were sent in this session (`melfa.robot.edit`)."""
        """Directory position (``PDIRnn``) where each program was last listed."""
        self.jog_method: JogMethod | None = None
        """The jog method found to work (cached after the first jog)."""
        self._rights = False
        self._op_lock = threading.RLock()
        self._open_lock = threading.Lock()
        self._stop_generation = 0
        self._op_generation = 0

    @classmethod
    def open(
        cls,
        spec: str,
        link_settings: LinkSettings | None = None,
        settings: RobotSettings | None = None,
        *,
        trace: bool | None = None,
        trace_sink: Callable[[str], None] | None = None,
    ) -> Robot:
        """Open the link ``spec`` names (see `melfa.robot.open_robot_link`) and wrap it;
        ``trace_sink`` receives the byte trace (``--trace FILE``)."""
        from melfa.robot.opener import open_robot_link  # lazily: it may import the simulator

        link = open_robot_link(spec, link_settings, trace=trace, trace_sink=trace_sink)
        return cls(link, settings)

    # ----------------------------------------------------------------- session basics

    def __enter__(self) -> Robot:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @property
    def edit_slot(self) -> int:
        """Slot for EMDAT: setting, else TASKMAX+1 from the banner, else 9."""
        if self.settings.edit_slot is not None:
            return self.settings.edit_slot
        if self.banner is not None and self.banner.edit_slot is not None:
            return self.banner.edit_slot
        return EDIT_SLOT

    def connect(self) -> OpenBanner:
        """Open the session once (``OPEN=<client name>``); later calls return the banner.

        A banner that cannot be read ends the session (link closed, `RemoteProtocolError`):
        whatever answers is not a controller we understand, or the line settings are wrong.
        """
        with self._open_lock:
            if self.banner is None:
                command = f"OPEN={self.settings.client_name}"
                try:
                    reply = self._send(command)
                    ok = self._expect_ok(reply, command)
                    self.banner = OpenBanner.parse(ok.answer)
                except RemoteProtocolError as exc:
                    self.link.close()
                    raise RemoteProtocolError(
                        f"unreadable answer to OPEN ({exc}); session ended. Check that the "
                        "line settings match the controller (9600 8E2 by default)"
                    ) from None
            return self.banner

    def close(self) -> None:
        """Release the rights, end the session, close the link. Never raises."""
        with contextlib.suppress(Exception):
            if not self.link.closed and self.banner is not None:
                if self._rights:
                    self._send("CNTLOFF")
                self._send("CLOSE")
        self._rights = False
        self.banner = None
        self.handshaken = False
        self.link.close()

    def request(self, command: str, *, slot: int | None = None, timeout: float | None = None) -> Ok:
        """Send any command (opening the session and taking rights as needed); the reply,
        or `ControllerError` if refused."""
        with self._operation():
            return self._call(command, slot=slot, timeout=timeout)

    # ------------------------------------------------------------------------ program

    def upload_program(
        self, plan: UploadPlan, progress: Progress | None = None, *, verify: bool = False
    ) -> UploadReport:
        """Replace program `settings.program` (slot program "1") with the plan's program
        (`melfa.lang.plan.plan_upload`).

        Sequence and guarantees: `melfa.robot.edit` (slot reset, NEW, LOAD=, ECLR, EMDAT…,
        a self-identifying PARRLNG before SAVE, PDIR confirmation, read-back on ``verify``).
        On any failure the edit is closed with NEW, so the old program stays. An
        `UploadRefused` names the line and column in the program. ECLR also clears the
        program's positions: use `load_project` to send both.
        """
        with self._operation() as generation:
            return edit.write_program(
                self,
                sendable(plan),
                generation,
                progress,
                clear=self.settings.clear_with_eclr,
                verify=verify,
            )

    def upload_points(
        self, plan: UploadPlan, progress: Progress | None = None, *, verify: bool = False
    ) -> UploadReport:
        """Add or replace the plan's positions in the program, keeping its steps (no
        ECLR)."""
        with self._operation() as generation:
            return edit.write_program(
                self, sendable(plan), generation, progress, clear=False, verify=verify
            )

    def load_project(
        self, plan: UploadPlan, progress: Progress | None = None, *, verify: bool = False
    ) -> UploadReport:
        """The plan's program and points in one LOAD…SAVE session (they live in the same
        program, and one session saves the NEW/LOAD/handshake/SAVE round trips of a second
        one).

        This is the thesis's "load project" (delete, program, points), with the delete done
        *inside* the edit: ``ECLR`` clears the old steps and positions [DOC S1 §5.2; TRACE
        S21], so nothing of the old program survives a successful upload, and a failed one
        leaves the old program whole (the thesis's FDEL first would have lost it)."""
        with self._operation() as generation:
            return edit.write_program(
                self, sendable(plan), generation, progress, clear=True, verify=verify
            )

    def find_program(self) -> edit.ProgramEntry | None:
        """What PDIR lists for program `settings.program`, or None."""
        with self._operation():
            return edit.find_program(self, self.settings.program)

    def delete(self) -> None:
        """Delete the program and its points: slot reset under rights (CNTLON, SLOTINIT),
        then FDEL<program>, as RT ToolBox does [TRACE K9b-DEL]. Deleting a program that
        does not exist is not an error."""
        with self._operation():
            edit.reset_slot(self)
            try:
                self._call(f"FDEL{self.settings.program}")
            except ControllerError as exc:
                if exc.number != PROGRAM_NOT_FOUND:
                    raise

    def run(self, *, resume: bool = False) -> None:
        """Start the program from its beginning: slot reset (``SLOTINIT``) under rights,
        then ``RUN<program>;1`` (cycle mode) [TRACE K9b-RUN; S7 ``1;1;RUN1;1``]. With
        ``resume`` a program paused by STOP continues where it stopped (no reset)."""
        with self._operation():
            if not resume:
                edit.reset_slot(self)
            mode = 1 if self.settings.cycle_mode else 0
            self._call(f"RUN{self.settings.program};{mode}")

    def reset_program(self) -> None:
        """``RSTPRG`` under operation rights: back to the program's first line."""
        with self._operation():
            self._call("RSTPRG")

    def stop(self) -> None:
        """Stop: ``1;1;STOP``, the form real serial clients send (`settings.stop_slot`;
        0 gives the manual's all-slots ``1;0;STOP``) [DOC S5: always allowed, no rights].

        Callable from any thread at any time. It never waits behind the worker: the STOP
        bytes go out at once, even while another request awaits its reply, never behind a
        resynchronisation. Then any multi-request operation in progress (upload, jog, wait)
        raises `Stopped` at its next step; an upload closes its edit with NEW. STOP
        succeeds when the controller accepted it, even if an earlier request is never
        answered (`melfa.robot.channel`).
        """
        self._stop_generation += 1
        if self.banner is None:
            self.connect()
        reply = self.channel.stop(
            Request("STOP", robot=self.settings.robot, slot=self.settings.stop_slot)
        )
        self._note(reply)
        if not isinstance(reply, Ok):
            raise self._refusal(reply, "STOP", fetch=False)

    def wait_idle(
        self,
        timeout: float = 60.0,
        poll: float = 0.2,
        on_state: Callable[[DState], object] | None = None,
    ) -> DState:
        """Poll ``STATE`` until the RUN bit (0x40) clears [DOC S1 p.55; ≥ 100 ms spacing
        while running, DOC S1 §3.3.3]. `Stopped` if `stop` is called meanwhile.
        ``on_state`` sees each state read while it runs (a command line's progress)."""
        with self._operation() as generation:
            end = time.monotonic() + timeout
            while True:
                state = self._status()
                if RunStatus.RUNNING not in state.status.run:
                    return state
                if on_state is not None:
                    on_state(state)
                if time.monotonic() > end:
                    raise RobotError(f"still running after {timeout:g} s")
                self._checkpoint(generation)
                time.sleep(poll)
                self._checkpoint(generation)

    # ----------------------------------------------------------------- single actions

    def exec(self, statement: str) -> None:
        """Execute one MELFA BASIC statement now: ``EXEC<statement>`` (replies when accepted,
        not when done [DOC S1 §5.2.16])."""
        with self._operation():
            self._call("EXEC" + statement.strip())

    def servo(self, on: bool) -> None:
        """``SRVON`` (needs rights) / ``SRVOFF``."""
        with self._operation():
            self._call("SRVON" if on else "SRVOFF")

    def override(self, percent: int) -> int:
        """Set the operation-panel override (`OVERRIDE_PERCENT`, ``OVRD=``); returns the new
        value."""
        if percent not in OVERRIDE_PERCENT:
            raise LocalProtocolError(
                f"override {percent} % is outside {span_text(OVERRIDE_PERCENT)}"
            )
        with self._operation():
            answer = self._call(f"OVRD={percent}").answer
            return int(answer) if answer.isdigit() else percent

    def hand(self, open_: bool, number: int = 1) -> None:
        """Open or close hand ``number`` (`HANDS`). Default ``EXECHOPEN n``/``EXECHCLOSE n``."""
        if number not in HANDS:
            raise LocalProtocolError(f"hand {number} is outside {span_text(HANDS)}")
        with self._operation():
            if self.settings.hand is HandMethod.EXEC:
                self._call(f"EXEC{'HOPEN' if open_ else 'HCLOSE'} {number}")
            else:
                on = open_ == self.settings.hnd_on_opens
                self._call(f"{'HNDON' if on else 'HNDOFF'}{number}")

    def reset_alarm(self) -> Alarm | None:
        """``RSTALRM`` (needs rights); then ``ERROR`` again. Returns the alarm still active
        after the reset (one that cannot be reset this way: an emergency stop, a fault
        that is still there), or None when all is clear."""
        with self._operation():
            self._call("RSTALRM")
            self.alarm = False
            return self.active_alarm()

    def active_alarm(self) -> Alarm | None:
        """The active error with its text, or None: the error field of ``STATE``, then
        ``ERRORMES`` (real controllers were recorded answering both; ``ERROR`` never was)."""
        with self._operation():
            return self._alarm_of(State.parse(self._call("STATE").answer))

    def _alarm_of(self, state: State) -> Alarm | None:
        number = state.status.error
        if not number:
            return None
        return Alarm(number, self._error_message(number), error_level(number))

    def status(self) -> ControllerStatus:
        """``STATE`` plus the active alarm's text: what ``melfa status`` shows."""
        with self._operation():
            state = State.parse(self._call("STATE").answer)
            return ControllerStatus(state, self._alarm_of(state))

    def error_text(self, number: int) -> str:
        """The controller's text for an error (``ERRORMES<n>``), else melfa's table."""
        with self._operation():
            return self._error_message(number)

    def current_error(self) -> ErrorStatus | None:
        """``ERROR``: the active error, or None."""
        with self._operation():
            return ErrorStatus.parse(self._call("ERROR").answer)

    # ------------------------------------------------------------------------ reading

    def joints(self) -> Position:
        """``JPOSF``: J1…J6 in degrees (`Position.values(*JOINT_NAMES)`)."""
        with self._operation():
            return Position.parse(self._call("JPOSF").answer)

    def pose(self) -> Position:
        """``PPOSF``: X, Y, Z (mm), A, B, C (degrees), FL1/FL2, override, speed."""
        with self._operation():
            return Position.parse(self._call("PPOSF").answer)

    def state(self) -> State:
        """``STATE``: program, line, override, run/stop status bits, error."""
        with self._operation():
            return State.parse(self._call("STATE").answer)

    def hand_status(self) -> HandStatus:
        """``HNDSTS``: each hand open, closed or unknown."""
        with self._operation():
            return HandStatus.parse(self._call("HNDSTS").answer)

    def dstate(self) -> DState:
        """The short status (run/stop bits, error, line), read with ``STATE``: a real
        controller's answer to STATE is on record, to ``DSTATE`` none is [TRACE K9b]."""
        with self._operation():
            return self._status()

    def _status(self) -> DState:
        state = State.parse(self._call("STATE").answer)
        return DState(state.status, state.line, state.mechanism)

    # --------------------------------------------------------------------------- jog

    def jog(self, mode: JogMode, axis: int, direction: int) -> JogMethod:
        """Move one axis while called repeatedly (every ≤ 100 ms; the controller stops a JOG
        not renewed within ~140 ms [DOC S1 §5.2.59]). Returns the method used.

        `JogMethod.AUTO`: JOG first; if the firmware refuses it (L2030, 6010) switch to step
        moves for the rest of the session: one small ``EXECMVS``/``EXECMOV`` relative move
        per call, skipped (not queued) while the previous step still moves (5640).
        """
        request = Jog.axis(mode, axis, direction)  # checks axis/direction first
        with self._operation():
            method = self.jog_method or self.settings.jog
            if method is not JogMethod.STEP:
                reply = self._raw(request.command, rights=True)
                if isinstance(reply, Ok):
                    self.jog_method = JogMethod.JOG
                    return JogMethod.JOG
                if method is JogMethod.JOG or getattr(reply, "error", 0) not in JOG_NOT_ACCEPTED:
                    raise self._refusal(reply, request.command)
                self.jog_method = JogMethod.STEP
            try:
                for statement in self.step_statements(mode, axis, direction):
                    self._call("EXEC" + statement)
            except ControllerError as exc:
                if exc.number != BUSY:
                    raise
            return JogMethod.STEP

    def jog_stop(self) -> None:
        """End a jog now: JOG with empty masks. A step jog's move is stopped with STOP:
        left alone it would run to the end of its step (up to `jog_step_mm`) after the key
        was let go, and the arm moves only while a key is held."""
        if self.jog_method is JogMethod.STEP:
            self.stop()
            return
        with self._operation():
            if self.jog_method is JogMethod.JOG:
                self._call(Jog(JogMode.JOINT).command)

    def step_statements(
        self, mode: JogMode, axis: int, direction: int, step_mm: float | None = None
    ) -> list[str]:
        """The relative move a step jog sends. Joint: ``JMJOG=(…)`` then
        ``MOV J_CURR+JMJOG`` (a bare ``(…)`` constant is a position, so joint offsets go
        through a J variable, as S18 does); world: ``MVS P_CURR+(…)`` [melfa-basic-iv §7];
        tool frame: ``MVS P_CURR*(…)`` [CODE S19]. ``step_mm`` overrides
        `RobotSettings.jog_step_mm` (the thesis's node stepped 20 mm)."""
        size = self.settings.jog_step_deg if mode is JogMode.JOINT or axis >= 3 else None
        linear = self.settings.jog_step_mm if step_mm is None else step_mm
        step = (size if size is not None else linear) * direction
        values = ["0"] * 6
        values[min(axis, 5)] = f"{step:g}"
        offset = "(" + ",".join(values) + ")"
        if mode is JogMode.JOINT:
            return [f"{JOG_JOINT_VARIABLE}={offset}", f"MOV J_CURR+{JOG_JOINT_VARIABLE}"]
        if mode is JogMode.TOOL:
            return [f"MVS P_CURR*{offset}"]
        return [f"MVS P_CURR+{offset}"]

    # ----------------------------------------------------------------------- plumbing

    @contextlib.contextmanager
    def _operation(self) -> Iterator[int]:
        with self._op_lock:
            generation = self._stop_generation
            yield generation

    def _checkpoint(self, generation: int) -> None:
        if self._stop_generation != generation:
            raise Stopped("stopped by request")

    def _send(self, command: str, slot: int | None = None, timeout: float | None = None) -> Reply:
        request = Request(
            command, robot=self.settings.robot, slot=self.settings.slot if slot is None else slot
        )
        reply = self.channel.request(request, timeout)
        self._note(reply)
        return reply

    def _note(self, reply: Reply) -> None:
        self.alarm = reply.alarm

    def _raw(
        self,
        command: str,
        *,
        slot: int | None = None,
        timeout: float | None = None,
        rights: bool | None = None,
    ) -> Reply:
        """Send with session and rights handled; the reply as it is (refusals included)."""
        if self.banner is None:
            self.connect()
        if rights if rights is not None else needs_rights(command):
            self._take_rights()
            reply = self._send(command, slot, timeout)
            if isinstance(reply, Refused) and reply.error == NO_RIGHTS:
                self._rights = False  # lost them (mode switch, T/B): take them again once
                self._take_rights()
                reply = self._send(command, slot, timeout)
            return reply
        return self._send(command, slot, timeout)

    def _call(self, command: str, *, slot: int | None = None, timeout: float | None = None) -> Ok:
        return self._expect_ok(self._raw(command, slot=slot, timeout=timeout), command)

    def _take_rights(self) -> None:
        if not self._rights:
            self._expect_ok(self._send("CNTLON"), "CNTLON")
            self._rights = True

    def _expect_ok(self, reply: Reply, command: str) -> Ok:
        if isinstance(reply, Ok):
            return reply
        raise self._refusal(reply, command)

    def _refusal(self, reply: Reply, command: str, *, fetch: bool = True) -> ControllerError:
        code = getattr(reply, "code", None)
        number = code.number if isinstance(code, ErrorCode) else 0
        wire = code.wire if isinstance(code, ErrorCode) else None
        message = self._error_message(number, wire) if fetch else error_text(number)
        shown = command if len(command) <= COMMAND_SHOWN else command[: COMMAND_SHOWN - 1] + "…"
        return ControllerError(number, message, command=shown, alarm=reply.alarm, code=wire)

    def _error_message(self, number: int, wire: str | None = None) -> str:
        """The controller's text: ``ERRORMES`` with the number exactly as it was received
        (9 digits after a 9-digit refusal, as RT ToolBox asks [TRACE K9b-PROG]), with the
        level letter from melfa's table; the table's text if that fails."""
        fallback = error_text(number)
        if not self.settings.fetch_error_text or self.banner is None:
            return fallback
        try:
            reply = self._send(f"ERRORMES{wire or f'{number:04d}'}")
        except (LinkError, LocalProtocolError):
            raise
        except Exception:
            return fallback
        if isinstance(reply, Ok) and reply.answer.strip():
            known = error_level(number) is not None
            return f"{error_code(number)} {reply.answer.strip()}" if known else reply.answer
        return fallback

    def _release_rights(self) -> None:
        """``CNTLOFF`` if the rights are held (RT ToolBox releases them before editing)."""
        if self._rights:
            self._expect_ok(self._send("CNTLOFF"), "CNTLOFF")
            self._rights = False
