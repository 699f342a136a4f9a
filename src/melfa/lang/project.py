"""Checking a project: programs and points files together, as one function.

`check_project` is what `melfa check`, the web API (and through it the IDE and the desktop
client) call: points files are read (`melfa.lang.points_read`), programs are checked against the
names they define (`melfa.lang.check`, step numbering included), and the points are judged
against the robot by the `reach` function the caller passes (`melfa.kin.reach`
.reach_diagnostics: the robot model sits above this package, so it is handed in).

Points files are read knowing the programs' declarations: ``DEF POS GET_BOX`` in the program
makes ``GET_BOX=(…)(7,0)`` an XYZ position although its name does not start with P.

Reach is judged only for points a program may move to. A point used only as an offset
(the right side of ``P1 + PUP``, ``P1 * POFF``: melfa-basic-iv.md §7) or only as tool or
base data (``TOOL PHAND``, §4.4) is never a place the arm goes, so
``DEF POS PUP=(0,0,30,0,0,0)`` gets no "out of reach" warning. Positions as the
arm actually reaches them are judged better by the simulator's pre-flight.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Iterable, Sequence

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.check import check_ast, internal_error
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.lexer import tokenize
from melfa.lang.parser import parse_tokens
from melfa.lang.points import PointDef, PointKind, PointsFile
from melfa.lang.points_read import parse_points
from melfa.lang.record import Record
from melfa.lang.reparse import EDITOR
from melfa.lang.tokens import Token

ReachCheck = Callable[[Sequence[PointDef], str], list[Diagnostic]]
"""(points, the points file's text) -> warnings; `melfa.kin.reach.reach_diagnostics`."""

_OFFSET_OPS = frozenset({A.BinaryOp.ADD, A.BinaryOp.SUB, A.BinaryOp.MUL, A.BinaryOp.DIV})
_ORDER = {Severity.ERROR: 0, Severity.WARNING: 1, Severity.INFO: 2}


class ProjectReport(Record):
    """Diagnostics per file, each list sorted by position (errors first on a tie)."""

    programs: tuple[tuple[Diagnostic, ...], ...]
    points: tuple[tuple[Diagnostic, ...], ...]

    @property
    def has_errors(self) -> bool:
        return any(d.is_error for found in (*self.programs, *self.points) for d in found)


def by_position(diagnostics: Iterable[Diagnostic]) -> tuple[Diagnostic, ...]:
    return tuple(sorted(diagnostics, key=lambda d: (d.line, d.column, _ORDER[d.severity])))


_FRAMES = frozenset({A.CommandKind.TOOL, A.CommandKind.BASE})
_DECLARED_POINTS = {A.VarType.POS: PointKind.POS, A.VarType.JNT: PointKind.JNT}


def declared_points(programs: Iterable[A.Program]) -> dict[str, PointKind]:
    """The names (upper case) the programs declare with DEF POS or DEF JNT (§4.6)."""
    found: dict[str, PointKind] = {}
    for program in programs:
        for line in program.lines:
            stmt = line.statement
            if isinstance(stmt, A.DefVar) and stmt.type in _DECLARED_POINTS:
                for name in stmt.names:
                    found.setdefault(name.name, _DECLARED_POINTS[stmt.type])
    return found


def points_of(program: str, points: str) -> PointsFile:
    """A points file read with what its program declares (`GET_BOX` after DEF POS GET_BOX),
    as `check_project` and the upload plan read it; for the simulators' loading."""
    return parse_points(points, declared_points([parse_tokens(tokenize(program))]))


def offset_only(program: A.Program) -> set[str]:
    """Names (upper case) used only as the right operand of position arithmetic (§7) or
    as the data of TOOL and BASE (§4.4): never a place the arm moves to."""
    uses: Counter[str] = Counter()
    offsets: Counter[str] = Counter()
    for line in program.lines:
        if line.statement is None:
            continue
        for node in A.walk(line.statement):
            if type(node) is A.Name:
                assert isinstance(node, A.Name)
                uses[node.name] += 1
            elif type(node) is A.Command:
                assert isinstance(node, A.Command)
                if node.kind in _FRAMES and node.args and type(node.args[0]) is A.Name:
                    frame = node.args[0]
                    assert isinstance(frame, A.Name)
                    offsets[frame.name] += 1
            elif type(node) is A.Binary:
                assert isinstance(node, A.Binary)
                right = node.right
                if node.op in _OFFSET_OPS and type(right) is A.Name:
                    assert isinstance(right, A.Name)
                    offsets[right.name] += 1
    return {name for name, count in offsets.items() if uses[name] == count}


def parse_program(tokens: list[Token] | str) -> A.Program | Exception:
    """The tree of a program's tokens, or of its text (only the lines not seen before are
    parsed: `melfa.lang.reparse.EDITOR`), or the exception a bug of ours raised (kept, to be
    reported as a diagnostic by `check_program`: it must not take the editor down)."""
    try:
        return EDITOR.parse(tokens) if isinstance(tokens, str) else parse_tokens(tokens)
    except Exception as exc:
        return exc


def check_program(
    program: A.Program | Exception, names: Sequence[str]
) -> tuple[tuple[Diagnostic, ...], set[str] | None]:
    """One program checked against the point `names`: its diagnostics sorted by position,
    and the names it uses only as offsets (None when the checker failed). The upload plan
    (`melfa.lang.plan`) calls this on the tree of the tokens it numbers, so a load
    tokenizes once."""
    try:
        if isinstance(program, Exception):
            raise program
        found = check_ast(program, names)
        offsets = offset_only(program)
    except Exception as exc:  # a bug of ours must not take the editor down
        return by_position([internal_error(exc)]), None
    return by_position(found), offsets


def check_project(
    programs: Sequence[str], points: Sequence[str] = (), reach: ReachCheck | None = None
) -> ProjectReport:
    """Check `programs` against the names the `points` files define; never raises.

    >>> report = check_project(["10 MOV P1 + PUP\\n"], ["P1=(400,0,600,180,0,180)(7,0)"])
    >>> [d.message for d in report.programs[0]], report.points
    (['Position PUP is not defined'], ((),))
    """
    parsed = [parse_program(text) for text in programs]
    trees = [p for p in parsed if isinstance(p, A.Program)]
    declared = declared_points(trees)
    files = [parse_points(text, declared) for text in points]
    names = [name for f in files for name in f.names]
    program_reports = []
    offsets: list[set[str]] = []
    for program in parsed:
        checked, offsets_here = check_program(program, names)
        if offsets_here is not None:
            offsets.append(offsets_here)
        program_reports.append(checked)
    skip = set.intersection(*offsets) if offsets else set()
    point_reports = []
    for text, f in zip(points, files, strict=True):
        found = list(f.diagnostics)
        targets = [p for p in f.points if p.name.upper() not in skip]
        if reach is not None and targets:
            found.extend(reach(targets, text))
        point_reports.append(by_position(found))
    return ProjectReport(tuple(program_reports), tuple(point_reports))
