"""Reading a points file (`melfa.lang.points`): text in, `PointsFile` out, never raising.

Both forms are read, and lines may mix them: the project's `DEF POS Pa=(…)(7,0)` and the
controller's `Pa=(…)(7,0)` (protocol.md §4.2 item 4). Comments (`'…`, `REM …`, and `*// …`
as COSIMIR writes them after a point) and blank lines are skipped. The `(…)(fl1,fl2)`
constant itself is read by the program parser (`melfa.lang.parser.parse_constant`): one
reading of constants for programs and points. FL2 is read from decimal, `&H…` or `&B…`.
What is wrong becomes a `Diagnostic` on its line, in the program checker's words and codes;
a file that is something else (a program, an R-protocol log) is one finding.
"""

from __future__ import annotations

import re
from collections.abc import Mapping

from melfa.lang.ast import JOINT_ELEMENTS, POSITION_ELEMENTS, Expr, constant_number
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.parser import parse_constant
from melfa.lang.points import (
    DEFAULT_FL1,
    DEFAULT_FL2,
    FL2_MASK,
    MAX_ELEMENTS,
    MAX_NAME_LENGTH,
    MIN_ELEMENTS,
    PointDef,
    PointKind,
    PointsFile,
)

__all__ = ["parse_points"]

# A name as programs write one (the lexer's word, melfa-basic-iv §2.1), or an array
# element of one: PMAG(1), PGRID(2,3).
_NAME = re.compile(r"([A-Za-z0-9_]+)(\(\s*\d+(?:\s*,\s*\d+){0,2}\s*\))?\Z")
# Lines of an R-protocol command log (`1;1;EXECP1=(…)`, protocol.md) and of a program.
_PROTOCOL_LINE = re.compile(r"\s*\d+;\d+;")
_PROGRAM_LINE = re.compile(r"\s*\d+\s+[*A-Za-z']")
_DEF = re.compile(r"(\s*)DEF(\s+)(\S+)(\s+)", re.IGNORECASE)
_LINE_BREAK = re.compile(r"\r\n|\r|\n")  # the line ends programs have too (CR alone: old Macs)
_REM = re.compile(r"\s*REM(\s|\Z)", re.IGNORECASE)

_SUGGEST_POS = "Write it as DEF POS Pname=(x,y,z,a,b,c)(7,0)."
_SUGGEST_JNT = "Write it as DEF JNT Jname=(j1,j2,j3,j4,j5,j6)."


class _LineError(Exception):
    """A line cannot be read; carries the diagnostic (internal)."""

    def __init__(self, diagnostic: Diagnostic) -> None:
        super().__init__(diagnostic.message)
        self.diagnostic = diagnostic


def _diag(
    line: int,
    start: int,
    end: int,
    message: str,
    rule: str,
    *,
    severity: Severity = Severity.ERROR,
    code: str | None = None,
    suggestion: str | None = None,
) -> Diagnostic:
    """A diagnostic on one line; `start`/`end` are 0-based string indices."""
    return Diagnostic(
        line=line,
        column=start + 1,
        end_line=line,
        end_column=max(end, start + 1) + 1,
        severity=severity,
        message=message,
        rule=rule,
        code=code,
        suggestion=suggestion,
    )


def _strip_comment(text: str) -> str:
    """The line without its comment: ``' …``, a whole ``REM …`` line, or ``*// …`` as
    COSIMIR writes after a point (``P1=(…)(6,0) *// Home``, melfa-basic-iv.md §4.1)."""
    if _REM.match(text):
        return ""
    for mark in ("'", "*//"):
        at = text.find(mark)
        if at >= 0:
            text = text[:at]
    return text


def _first_column(items: tuple[Expr | None, ...], default: int) -> int:
    """The 1-based column of the first written item, else `default`."""
    return next((e.span.column for e in items if e is not None), default)


def _where(text: str, expr: Expr | None, default: int) -> tuple[int, str]:
    """(0-based column, text as written) of an element, for messages."""
    if expr is None:
        return default, ""
    span = expr.span
    return span.column - 1, text[span.column - 1 : span.end_column - 1]


def _read_number(
    text: str, expr: Expr | None, lineno: int, index: int, kind: PointKind
) -> float | None:
    if expr is None:
        return None
    value = constant_number(expr)
    if value is None:
        col, item = _where(text, expr, 0)
        label = _element_label(kind, index)
        raise _LineError(
            _diag(
                lineno,
                col,
                col + len(item),
                f"{label} is not a number: {item!r}",
                "points-number",
                code="L3860",
                suggestion="Write numbers like 417.61 or -93.07 (mm and degrees).",
            )
        )
    return float(value)


def _element_label(kind: PointKind, index: int) -> str:
    return (JOINT_ELEMENTS if kind is PointKind.JNT else POSITION_ELEMENTS)[index]


def _read_flag(text: str, expr: Expr | None, lineno: int, which: str) -> int | None:
    if expr is None:
        return None
    value = constant_number(expr)
    if isinstance(value, int):
        return value
    col, item = _where(text, expr, 0)
    raise _LineError(
        _diag(
            lineno,
            col,
            col + len(item),
            f"Structure flag {which} must be a whole number (or &H…), got {item!r}",
            "points-flags",
            code="L3860",
            suggestion="Write FL1 as 0 to 7 (7 = right, above, non-flip) and FL2 as 0 or &H….",
        )
    )


def _kind_from_name(name: str) -> PointKind | None:
    first = name[:1].upper()
    return {"P": PointKind.POS, "J": PointKind.JNT}.get(first)


def _base_name(name: str) -> str:
    """``PMAG`` of the array element ``PMAG(1)``; the name itself otherwise."""
    return name.split("(", 1)[0].strip()


def _check_name(
    name: str, col: int, lineno: int, kind: PointKind, out: list[Diagnostic], declared: bool
) -> None:
    """The program's name rule (melfa-basic-iv §2.1): letters, digits and `_`, a letter
    first, at most 8 characters; `declared`: the program gives its kind with DEF POS/JNT."""
    end = col + len(name)
    match = _NAME.match(name)
    if not match or not name[0].isalpha():
        raise _LineError(
            _diag(
                lineno,
                col,
                end,
                f"{name!r} is not a valid name: use letters and digits, starting with a letter",
                "points-name",
                code="L4310",
            )
        )
    name = match.group(1)
    end = col + len(name)
    want = "P" if kind is PointKind.POS else "J"
    if name[0].upper() != want and not declared:
        what = (
            "an XYZ position (DEF POS)" if kind is PointKind.POS else "a joint position (DEF JNT)"
        )
        raise _LineError(
            _diag(
                lineno,
                col,
                end,
                f"{name} is {what}, so its name must start with {want}",
                "points-name",
                code="L4390",
                suggestion=f"Rename it {want}{name}."
                if len(name) < MAX_NAME_LENGTH
                else f"Rename it {want}{name[1:]}.",
            )
        )
    if len(name) > MAX_NAME_LENGTH:
        out.append(
            _diag(
                lineno,
                col,
                end,
                f"{name} is {len(name)} characters long; MELFA BASIC IV names are at most "
                f"{MAX_NAME_LENGTH}",
                "points-name",
                code="L4300",
                suggestion=f"Shorten it, e.g. {name[:MAX_NAME_LENGTH]}.",
            )
        )
    if name[1:2] == "_":  # `_` further on is allowed, as in programs (pSafe_1)
        out.append(
            _diag(
                lineno,
                col,
                end,
                f"{name} has '_' as its second character, which makes it an external "
                "variable shared by every program",
                "points-name",
                severity=Severity.WARNING,
                suggestion="Drop the '_' unless the point really is global.",
            )
        )


def _parse_line(
    raw: str, lineno: int, out: list[Diagnostic], declared: Mapping[str, PointKind]
) -> tuple[str, PointDef | None]:
    """Read one non-blank line. Returns (name or "", point or None); errors via _LineError."""
    text = _strip_comment(raw).rstrip()
    pos = 0
    kind: PointKind | None = None
    if m := _DEF.match(text):
        word = m.group(3).upper()
        if word not in ("POS", "JNT"):
            raise _LineError(
                _diag(
                    lineno,
                    m.start(3),
                    m.end(3),
                    f"DEF {m.group(3)} does not belong in a points file; only DEF POS and "
                    "DEF JNT lines do",
                    "points-syntax",
                    code="L4220",
                    suggestion="Move variable declarations into the program.",
                )
            )
        kind = PointKind(word)
        pos = m.end()
    eq = text.find("=", pos)
    if eq < 0:
        start = len(text) - len(text.lstrip())
        raise _LineError(
            _diag(
                lineno,
                start,
                len(text),
                "Expected a point: Name=(…)",
                "points-syntax",
                code="L4220",
                suggestion=_SUGGEST_POS,
            )
        )
    name_part = text[pos:eq]
    name = name_part.strip()
    name_col = pos + len(name_part) - len(name_part.lstrip())
    if not name:
        raise _LineError(
            _diag(
                lineno,
                eq,
                eq + 1,
                "The point has no name before '='",
                "points-syntax",
                code="L4220",
                suggestion=_SUGGEST_POS,
            )
        )
    given = declared.get(_base_name(name).upper())
    if kind is None:
        kind = given or _kind_from_name(name)
        if kind is None:
            raise _LineError(
                _diag(
                    lineno,
                    name_col,
                    name_col + len(name),
                    f"Cannot tell whether {name} is an XYZ position (P…) or a joint position (J…)",
                    "points-name",
                    code="L4390",
                    suggestion="Start the name with P or J, or write DEF POS or DEF JNT before it.",
                )
            )
    _check_name(name, name_col, lineno, kind, out, given is kind)

    literal, issue, end = parse_constant(text, eq + 2)
    if literal is None:
        assert issue is not None
        span = issue.span
        raise _LineError(
            _diag(
                lineno,
                span.column - 1,
                span.end_column - 1,
                issue.message,
                "points-syntax",
                code="L4220",
                suggestion=issue.suggestion
                or (_SUGGEST_POS if kind is PointKind.POS else _SUGGEST_JNT),
            )
        )
    items = literal.elements
    group_start, group_end = literal.span.column - 1, literal.span.end_column - 1
    if literal.flags is not None:  # the values' own ')' ends where the flags' '(' starts
        group_end = text.rindex("(", 0, _first_column(literal.flags, end) - 1)
    what = "X,Y,Z,A,B,C" if kind is PointKind.POS else "J1..J6"
    count = len(items)
    if not MIN_ELEMENTS <= count <= MAX_ELEMENTS:
        raise _LineError(
            _diag(
                lineno,
                group_start,
                group_end,
                f"{name} has {count} element{'s' if count != 1 else ''}; a "
                f"{'position' if kind is PointKind.POS else 'joint position'} has 6 ({what}), "
                f"or 8 with additional axes",
                "points-count",
                code="L3860",
                suggestion="Leave an element empty (e.g. 400,,300) rather than dropping it.",
            )
        )
    values = tuple(_read_number(text, item, lineno, i, kind) for i, item in enumerate(items))

    fl1: int | None = None
    fl2: int | None = None
    trailing = text[end - 1 :]
    if trailing.strip():
        start = end - 1 + len(trailing) - len(trailing.lstrip())
        raise _LineError(
            _diag(
                lineno,
                start,
                len(text),
                f"Unexpected text after the {'flags' if literal.flags else 'values'}: "
                f"{trailing.strip()!r}",
                "points-syntax",
                code="L4220",
            )
        )
    if literal.flags is not None:
        if kind is PointKind.JNT:
            raise _LineError(
                _diag(
                    lineno,
                    group_end,
                    len(text),
                    f"{name} is a joint position; joint positions have no structure flags",
                    "points-flags",
                    code="L3860",
                    suggestion="Remove the flags, or make it an XYZ position (DEF POS P…).",
                )
            )
        flags_start = group_end
        if len(literal.flags) != 2:
            raise _LineError(
                _diag(
                    lineno,
                    flags_start,
                    end - 1,
                    f"Structure flags are two numbers (FL1,FL2), found {len(literal.flags)}",
                    "points-flags",
                    code="L3860",
                    suggestion="Write two flags, e.g. (7,0) for a hand-down pose.",
                )
            )
        e1, e2 = literal.flags
        if e1 is None and e2 is None and not any(d.is_error and d.line == lineno for d in out):
            # `(,)`: RT ToolBox's "no data" for a position never taught [S2 p.146, S10].
            out.append(
                _diag(
                    lineno,
                    name_col,
                    name_col + len(name),
                    f"{name} has no data ((,) flags: a position never taught); it is not "
                    "uploaded or checked",
                    "points-no-data",
                    severity=Severity.INFO,
                )
            )
            return name, None
        fl1 = _read_flag(text, e1, lineno, "FL1")
        fl2 = _read_flag(text, e2, lineno, "FL2")
        c1, i1 = _where(text, e1, flags_start)
        c2, i2 = _where(text, e2, flags_start)
        if fl1 is not None and not 0 <= fl1 <= 7:
            out.append(
                _diag(
                    lineno,
                    c1,
                    c1 + len(i1),
                    f"FL1 {fl1} is outside 0..7 (RIGHT=4 + ABOVE=2 + NONFLIP=1)",
                    "points-flags",
                    code="L3860",
                )
            )
            fl1 = None
        if fl2 is not None and not -(2**31) <= fl2 <= FL2_MASK:
            out.append(
                _diag(
                    lineno,
                    c2,
                    c2 + len(i2),
                    f"FL2 {fl2} does not fit in 32 bits",
                    "points-flags",
                    code="L3860",
                )
            )
            fl2 = None
        if (fl1 is None or fl2 is None) and not any(d.is_error and d.line == lineno for d in out):
            out.append(
                _diag(
                    lineno,
                    flags_start,
                    end - 1,
                    f"{name}: omitted structure flags default to ({DEFAULT_FL1},{DEFAULT_FL2})",
                    "points-flags-default",
                    severity=Severity.INFO,
                )
            )
    elif kind is PointKind.POS:
        out.append(
            _diag(
                lineno,
                group_start,
                group_end,
                f"{name} has no structure flags; the controller uses ({DEFAULT_FL1},{DEFAULT_FL2})",
                "points-flags-default",
                severity=Severity.INFO,
                suggestion=f"Append ({DEFAULT_FL1},{DEFAULT_FL2}) to say so.",
            )
        )
    if any(d.is_error and d.line == lineno for d in out):
        return name, None
    if kind is PointKind.POS:
        return name, PointDef(
            name,
            kind,
            values,
            DEFAULT_FL1 if fl1 is None else fl1,
            DEFAULT_FL2 if fl2 is None else fl2 & FL2_MASK,
            line=lineno,
        )
    return name, PointDef(name, kind, values, line=lineno)


def parse_points(text: str, declared: Mapping[str, PointKind] | None = None) -> PointsFile:
    """Read a points file. Never raises: what is wrong becomes a diagnostic.

    `declared` gives the kinds the program declares (`DEF POS GET_BOX`; upper-case keys,
    `melfa.lang.project.declared_points`), so its names need not start with P or J.

    >>> f = parse_points("DEF POS Pa=(584.73,141.04,385.25,-163.74,1.11,-78.61)(7,0)")
    >>> f.points[0].name, f.points[0].values[0], f.points[0].fl1, f.diagnostics
    ('Pa', 584.73, 7, ())
    """
    points: list[PointDef] = []
    names: list[str] = []
    diagnostics: list[Diagnostic] = []
    first_line: dict[str, int] = {}
    lines = _LINE_BREAK.split(text)
    wrong = _wrong_file(lines)
    if wrong is not None:
        return PointsFile((), (wrong,), ())
    for lineno, raw in enumerate(lines, start=1):
        if not _strip_comment(raw).strip():
            continue
        line_diags: list[Diagnostic] = []
        try:
            name, point = _parse_line(raw, lineno, line_diags, declared or {})
        except _LineError as err:
            line_diags.append(err.diagnostic)
            name, point = _name_of_broken_line(raw), None
        diagnostics.extend(line_diags)
        if not name:
            continue
        key = name.upper()
        if key in first_line:
            col = raw.find(name)
            diagnostics.append(
                _diag(
                    lineno,
                    max(col, 0),
                    max(col, 0) + len(name),
                    f"{name} is already defined on line {first_line[key]}",
                    "points-duplicate",
                    code="L4350",
                    suggestion="Rename one of them (names ignore case).",
                )
            )
            continue
        first_line[key] = lineno
        names.append(name)
        if point is not None:
            points.append(point)
    return PointsFile(tuple(points), tuple(diagnostics), tuple(names))


def _wrong_file(lines: list[str]) -> Diagnostic | None:
    """One finding when most lines show the file is something else: an R-protocol command
    log (`1;1;EXECP1=(…)`, as PC tools record what they send, protocol.md) or a program."""
    written = [(n, line) for n, line in enumerate(lines, start=1) if _strip_comment(line).strip()]
    if not written:
        return None
    protocol = [n for n, line in written if _PROTOCOL_LINE.match(line)]
    program = [n for n, line in written if _PROGRAM_LINE.match(line)]
    if 2 * len(protocol) > len(written):
        first = protocol[0]
        return _diag(
            first,
            0,
            len(lines[first - 1]),
            "This file is an R-protocol command log (lines like 1;1;EXECP1=(…)), what a PC "
            "program sends to the controller, not a points file",
            "points-wrong-file",
            code="L4220",
            suggestion="Keep the Name=(…)(fl1,fl2) part after EXEC of each point in a points "
            "file of its own, one point a line.",
        )
    if 2 * len(program) > len(written):
        first = program[0]
        return _diag(
            first,
            0,
            len(lines[first - 1]),
            "This file is a program (numbered steps), not a points file",
            "points-wrong-file",
            code="L4220",
            suggestion="Open it as the program; a points file has one Name=(…) line a point.",
        )
    return None


def _name_of_broken_line(raw: str) -> str:
    """The name a broken line meant to define, if it is plain enough to tell."""
    m = re.match(r"\s*(?:DEF\s+(?:POS|JNT)\s+)?([A-Za-z][A-Za-z0-9_]*)\s*=", raw, re.IGNORECASE)
    return m.group(1) if m else ""
