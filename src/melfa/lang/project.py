"""Checking a project: programs and points files together, as one function.

`check_project` is what `melfa check`, the web API (and through it the IDE and the desktop
client) call: points files are read (`melfa.lang.points`), programs are checked against the
names they define (`melfa.lang.check`, step numbering included), and the points are judged
against the robot by the `reach` function the caller passes (`melfa.kin.reach`
.reach_diagnostics: the robot model sits above this package, so it is handed in).

Reach is judged only for points a program may move to. A point used only as an offset
(the right side of ``P1 + PUP``, ``P1 * POFF``: melfa-basic-iv.md §7) is never a place the
arm goes, so ``DEF POS PUP=(0,0,30,0,0,0)`` gets no "out of reach" warning. Positions as the
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
from melfa.lang.points import PointDef, parse_points
from melfa.lang.record import Record

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


def offset_only(program: A.Program) -> set[str]:
    """Names (upper case) used only as the right operand of position arithmetic (§7)."""
    uses: Counter[str] = Counter()
    offsets: Counter[str] = Counter()
    for line in program.lines:
        if line.statement is None:
            continue
        for node in A.walk(line.statement):
            if type(node) is A.Name:
                assert isinstance(node, A.Name)
                uses[node.name] += 1
            elif type(node) is A.Binary:
                assert isinstance(node, A.Binary)
                right = node.right
                if node.op in _OFFSET_OPS and type(right) is A.Name:
                    assert isinstance(right, A.Name)
                    offsets[right.name] += 1
    return {name for name, count in offsets.items() if uses[name] == count}


def check_project(
    programs: Sequence[str], points: Sequence[str] = (), reach: ReachCheck | None = None
) -> ProjectReport:
    """Check `programs` against the names the `points` files define; never raises.

    >>> report = check_project(["10 MOV P1 + PUP\\n"], ["P1=(400,0,600,180,0,180)(7,0)"])
    >>> [d.message for d in report.programs[0]], report.points
    (['Position PUP is not defined'], ((),))
    """
    files = [parse_points(text) for text in points]
    names = [name for f in files for name in f.names]
    program_reports = []
    offsets: list[set[str]] = []
    for text in programs:
        try:
            program = parse_tokens(tokenize(text))
            found = check_ast(program, names)
            offsets.append(offset_only(program))
        except Exception as exc:  # a bug of ours must not take the editor down
            found = [internal_error(exc)]
        program_reports.append(by_position(found))
    skip = set.intersection(*offsets) if offsets else set()
    point_reports = []
    for text, f in zip(points, files, strict=True):
        found = list(f.diagnostics)
        targets = [p for p in f.points if p.name.upper() not in skip]
        if reach is not None and targets:
            found.extend(reach(targets, text))
        point_reports.append(by_position(found))
    return ProjectReport(tuple(program_reports), tuple(point_reports))
