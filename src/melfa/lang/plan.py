"""The upload plan: everything a load needs, decided once from one tokenization.

`plan_upload` is what the CLI, the web API, ROS, the thesis's messages, the service and
`melfa.robot.Robot` use for a program and its points, so a program goes to the controller
the same way from every entry and every part reads the same answers:

- **the lines to send** (`UploadPlan.items`): comments and strings folded to ASCII
  (`melfa.lang.ascii`, line count unchanged); a program numbered already (every non-blank
  line starts with a step number, *by the tokens*: ``3END`` is step 3) is sent as it is,
  any other is numbered 10, 20, … with its jumps rewritten (`melfa.lang.numbering`);
  points read by `melfa.lang.points_read` and written in the controller's ``P1=(…)(7,0)`` form;
- **the step → line map** (`UploadPlan.step_lines`): which line of the user's own text
  each step number the controller reports is, for the running-line marker;
- **the diagnostics**: the checker's (`melfa.lang.project.check_program`, against the names
  the points define), the points file's, and what cannot be sent at all (a non-ASCII
  character in code, numbering that would change the meaning);
- **the fingerprint** the instructor's gate compares: a hash of what is sent, so the same
  program written numbered or not, with ``DEF POS`` or in the controller's form, is the same
  program to the gate, and any change to what reaches the controller is a different one.

Pure: no robot, no files. The program is tokenized once (`melfa.lang.lexer.tokenize`), the
points parsed once.

>>> plan = plan_upload("MOV P1 ' repòs\\nEND\\n", "DEF POS P1=(1,2,3,4,5,6)(7,0)\\n")
>>> [item.text for item in plan.items]
["10 MOV P1 ' repos", '20 END', 'P1=(1.00,2.00,3.00,4.00,5.00,6.00)(7,0)']
>>> plan.numbered, plan.step_lines, plan.note
(False, {10: 1, 20: 2}, 'comments on line 1 sent without accents; your file is unchanged')
>>> plan_upload("1 MOV P1\\n2 GOTO 1\\n3END").step_lines
{1: 1, 2: 2, 3: 3}
"""

from __future__ import annotations

import enum
import hashlib
import re
from collections.abc import Sequence

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.ascii import fold_tokens
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.lexer import tokenize
from melfa.lang.numbering import number_tokens
from melfa.lang.points_read import parse_points
from melfa.lang.points_write import upload_lines
from melfa.lang.project import by_position, check_program, declared_points, parse_program
from melfa.lang.record import Record

_LINE_BREAK = re.compile(r"\r\n|\r|\n")
"""Line breaks as the lexer sees them (not `str.splitlines`, which also splits at \\f)."""


class Part(enum.StrEnum):
    """Which text an item or a problem comes from."""

    PROGRAM = "program"
    POINTS = "points"


class UploadItem(Record):
    """One EMDAT item and where it came from (1-based line of the caller's text)."""

    text: str
    source_line: int
    source: Part = Part.PROGRAM


class Blocker(Record):
    """Why the plan cannot be sent at all (not even with ``--force``), and where."""

    source: Part
    diagnostic: Diagnostic


class UploadPlan(Record):
    """What goes to the controller and what every part needs to know about it."""

    program: str | None
    """The user's program text (None: points only)."""
    points: str | None
    """The user's points text (None: program only)."""
    items: tuple[UploadItem, ...]
    """In order: program steps, then points. Empty when `blocker` is set."""
    numbered: bool
    """The program was numbered already and is sent as it is."""
    step_lines: dict[int, int]
    """Step number the controller reports -> 1-based line of `program`."""
    diagnostics: tuple[Diagnostic, ...]
    """The program's, by position: the checker's and what cannot be sent."""
    point_diagnostics: tuple[Diagnostic, ...]
    fingerprint: str
    """What the instructor's gate compares: a hash of the lines sent (program and points)."""
    note: str | None = None
    """What was changed on the way (accents folded), for the user; None if nothing."""
    blocker: Blocker | None = None

    @property
    def has_program(self) -> bool:
        return self.program is not None

    @property
    def has_errors(self) -> bool:
        """An error in the program or the points: check-before-upload refuses it."""
        return any(d.is_error for d in (*self.diagnostics, *self.point_diagnostics))

    def first_error(self) -> tuple[Part, Diagnostic] | None:
        """The first error, program before points."""
        for part, found in (
            (Part.PROGRAM, self.diagnostics),
            (Part.POINTS, self.point_diagnostics),
        ):
            for d in found:
                if d.is_error:
                    return part, d
        return None

    @property
    def program_texts(self) -> tuple[str, ...]:
        """The program's steps as sent."""
        return tuple(i.text for i in self.items if i.source is Part.PROGRAM)

    @property
    def point_texts(self) -> tuple[str, ...]:
        """The points as sent (``P1=(…)(7,0)``)."""
        return tuple(i.text for i in self.items if i.source is Part.POINTS)

    @property
    def program_digest(self) -> str:
        """`digest` of the program as sent (the gate's record of what is loaded)."""
        return digest(self.program_texts)

    @property
    def points_digest(self) -> str:
        return digest(self.point_texts)

    @property
    def program_lines(self) -> int:
        return len(self.program_texts)

    @property
    def point_count(self) -> int:
        return len(self.point_texts)


def digest(lines: Sequence[str]) -> str:
    """A hash of lines as sent (the gate's unit)."""
    return hashlib.sha256("\n".join(lines).encode()).hexdigest()


def fingerprint_of(program_lines: Sequence[str], point_lines: Sequence[str]) -> str:
    """The gate's fingerprint of a program and its points as sent."""
    return hashlib.sha256(f"{digest(program_lines)}\0{digest(point_lines)}".encode()).hexdigest()


def _problem(line: int, column: int, message: str, rule: str, code: str) -> Diagnostic:
    return Diagnostic(line, column, line, column + 1, Severity.ERROR, message, rule, code)


def _non_ascii(lines: Sequence[str]) -> Diagnostic | None:
    for number, row in enumerate(lines, start=1):
        for column, char in enumerate(row, start=1):
            if not char.isascii():
                return _problem(
                    number,
                    column,
                    f"{char!r} is not ASCII and is not in a comment or string; the controller "
                    "only takes ASCII (rename it)",
                    "illegal-character",  # the checker's rule for it, so said once
                    "L4310",
                )
    return None


def _merge(found: tuple[Diagnostic, ...], more: Sequence[Diagnostic]) -> tuple[Diagnostic, ...]:
    """Add `more` to `found`, leaving out what the checker already said at that place."""
    seen = {(d.line, d.column, d.rule) for d in found}
    extra = [d for d in more if (d.line, d.column, d.rule) not in seen]
    return by_position((*found, *extra)) if extra else found


def plan_upload(program: str | None, points: str | None = None) -> UploadPlan:
    """The plan for `program` and/or `points` (see the module doc); never raises."""
    blocker: Blocker | None = None
    items: list[UploadItem] = []
    point_diags: tuple[Diagnostic, ...] = ()
    names: tuple[str, ...] = ()
    point_items: list[UploadItem] = []
    tokens = tokenize(program) if program is not None else None
    tree = parse_program(tokens) if tokens is not None else None
    if points is not None:
        declared = declared_points([tree]) if isinstance(tree, A.Program) else None
        parsed = parse_points(points, declared)
        names = parsed.names
        point_diags = by_position(parsed.diagnostics)
        errors = [d for d in point_diags if d.is_error]
        if errors:
            blocker = Blocker(Part.POINTS, errors[0])
        else:
            texts = upload_lines(parsed.points)
            point_items = [
                UploadItem(text, point.line or index + 1, Part.POINTS)
                for index, (point, text) in enumerate(zip(parsed.points, texts, strict=True))
            ]
    diagnostics: tuple[Diagnostic, ...] = ()
    numbered = False
    step_lines: dict[int, int] = {}
    note = None
    if tokens is not None and tree is not None:
        diagnostics, _ = check_program(tree, names)
        folded, conversion = fold_tokens(tokens)
        note = conversion.note()
        numbering = number_tokens(folded)
        numbered, step_lines = numbering.numbered, numbering.step_lines
        problems = list(numbering.diagnostics)
        bad = _non_ascii(_LINE_BREAK.split(conversion.text))
        if bad is not None:
            problems.insert(0, bad)
        diagnostics = _merge(diagnostics, problems)
        if problems:
            blocker = Blocker(Part.PROGRAM, problems[0])
        elif numbering.text is not None:
            lines = [line.rstrip(" \t") for line in _LINE_BREAK.split(numbering.text)]
            items = [
                UploadItem(line.strip(), index, Part.PROGRAM)
                for index, line in enumerate(lines, start=1)
                if line.strip()
            ]
    if blocker is not None:
        items, point_items = [], []
    items += point_items
    sent = tuple(items)
    return UploadPlan(
        program,
        points,
        sent,
        numbered,
        step_lines,
        diagnostics,
        point_diags,
        fingerprint_of(
            [i.text for i in sent if i.source is Part.PROGRAM],
            [i.text for i in sent if i.source is Part.POINTS],
        ),
        note,
        blocker,
    )


__all__ = ["Blocker", "Part", "UploadItem", "UploadPlan", "digest", "fingerprint_of", "plan_upload"]
