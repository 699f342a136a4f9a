"""Statements a program uses, read from the parse tree (the `uses` and `avoids` checks).

A statement is named by its keyword as a student writes it (``GOSUB``, ``MVS``, ``HOPEN``,
``FOR``, ``DEF FN``). ``GOTO`` means a written GOTO (``GOTO *L``, ``ON M GOTO …``); the jump
of ``IF … THEN *L`` is the IF's own and not counted as one. Statements inside an IF's
branch or after a move's WTH count too. Pure: the tree in, lines out.
"""

from __future__ import annotations

from collections.abc import Callable

from melfa.lang import ast as A  # noqa: N812

Match = Callable[[object], bool]


def _is(kind: type) -> Match:
    return lambda node: isinstance(node, kind)


def _jump(kind: A.JumpKind, plain: type) -> Match:
    return lambda node: (
        isinstance(node, plain) or (isinstance(node, A.OnJump) and node.kind is kind)
    )


def _command(kind: A.CommandKind) -> Match:
    return lambda node: isinstance(node, A.Command) and node.kind is kind


def _move(kind: A.MoveKind) -> Match:
    return lambda node: isinstance(node, A.Move) and node.kind is kind


def _arc(kind: A.ArcKind) -> Match:
    return lambda node: isinstance(node, A.ArcMove) and node.kind is kind


def _switch(kind: A.SwitchKind) -> Match:
    return lambda node: isinstance(node, A.Switch) and node.kind is kind


def _def(kind: A.VarType) -> Match:
    return lambda node: isinstance(node, A.DefVar) and node.type is kind


STATEMENTS: dict[str, Match] = {
    "GOTO": _jump(A.JumpKind.GOTO, A.Goto),
    "GOSUB": _jump(A.JumpKind.GOSUB, A.Gosub),
    "ON": _is(A.OnJump),
    "RETURN": _is(A.Return),
    "IF": _is(A.If),
    "FOR": _is(A.For),
    "WHILE": _is(A.While),
    "SELECT": _is(A.Select),
    "WAIT": _is(A.Wait),
    "MVA": _is(A.ArchMove),
    "CMP": _is(A.Cmp),
    "FPRM": _is(A.Fprm),
    "DEF FN": _is(A.DefFn),
    "DEF PLT": _is(A.DefPlt),
    "DEF ACT": _is(A.DefAct),
    "DEF IO": _is(A.DefIO),
    "ACT": _is(A.ActSet),
    "DIM": _is(A.Dim),
    "OPEN": _is(A.Open),
    "PRINT": _is(A.Print),
    "INPUT": _is(A.Input),
    "CLOSE": _is(A.Close),
    **{k.value: _move(k) for k in A.MoveKind},
    **{k.value: _arc(k) for k in A.ArcKind},
    **{k.value: _command(k) for k in A.CommandKind},
    **{k.value: _switch(k) for k in A.SwitchKind},
    **{f"DEF {k.value}": _def(k) for k in A.VarType},
}
"""Every statement name a check may use, upper case, and how to find it in the tree."""


def normalise(name: str) -> str:
    """``"def  fn"`` → ``"DEF FN"``; `KeyError`-free: unknown names come back as given."""
    return " ".join(name.upper().split())


def lines_using(program: A.Program, name: str) -> list[int]:
    """The lines (1-based) whose statement is, or contains, statement `name` (known)."""
    match = STATEMENTS[normalise(name)]
    found = []
    for number, line in enumerate(program.lines, start=1):
        if line.statement is not None and any(match(n) for n in A.walk(line.statement)):
            found.append(number)
    return found


def lines_setting_output(program: A.Program, bit: int) -> list[int]:
    """The lines that assign ``M_OUT(bit)`` (or ``M_OUT(expr)``, which may be it)."""
    found = []
    for number, line in enumerate(program.lines, start=1):
        if line.statement is None:
            continue
        for node in A.walk(line.statement):
            if not isinstance(node, A.Assign) or not isinstance(node.target, A.Index):
                continue
            target = node.target
            if target.name.name.upper() != "M_OUT" or not target.args:
                continue
            index = A.constant_number(target.args[0])
            if index is None or index == bit:
                found.append(number)
                break
    return found
