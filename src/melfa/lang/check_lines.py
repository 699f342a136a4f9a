"""Checks on lines as written: their length, their step numbers and their labels.

A mixin of the checker (`melfa.lang.check`), like `melfa.lang.check_names`: the passes over
the program's lines that read no statement (the controller's limits on a step's length, a
step number's range and order, a label's uniqueness and length).
"""

from __future__ import annotations

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.diagnostics import Severity
from melfa.lang.linetable import LineTable
from melfa.lang.model import MAX_LINE_LENGTH, MAX_LINE_NUMBER, MAX_NAME_LENGTH
from melfa.lang.reporter import Reporter

E, W = Severity.ERROR, Severity.WARNING


class LineChecks(Reporter):
    """line-too-long, line-number-*, duplicate-label, label-too-long; mixed into the
    checker's analyser."""

    program: A.Program
    table: LineTable

    def line_limits(self) -> None:
        if self.table.longest() - 1 <= MAX_LINE_LENGTH:
            return  # no line too long: not one to look at
        for line in self.program.lines:
            length = line.span.end_column - 1
            if length > MAX_LINE_LENGTH:
                span = A.Span(line.span.line, MAX_LINE_LENGTH + 1, line.span.line, length + 1)
                self.add(
                    span,
                    E,
                    f"Line is {length} characters long; the controller allows {MAX_LINE_LENGTH}",
                    "line-too-long",
                    "L4210",
                    "Split the statement over two lines, or use shorter names.",
                )

    def numbering(self) -> None:
        lines = self.program.lines
        numbered = self.table.numbered
        if not numbered:
            return
        # Editor form when a non-blank line has no number (the uploader's test, too).
        editor = any(
            line.number is None
            and (line.statement is not None or line.label is not None or line.comment is not None)
            for line in lines
        )
        seen: dict[int, int] = {}
        previous: int | None = None
        for index in numbered:
            line = lines[index]
            number, span = line.number, line.number_span
            if number is None or span is None:
                continue
            if not 1 <= number <= MAX_LINE_NUMBER:
                self.add(
                    span,
                    E,
                    f"Step number {number} is out of range",
                    "line-number-range",
                    "L4420",
                    f"Use a step number from 1 to {MAX_LINE_NUMBER}.",
                )
            if number in seen:
                why = "" if editor else "; the controller keeps only the last one"
                self.add(
                    span,
                    E,
                    f"Step number {number} is used twice (also on line {seen[number]}){why}",
                    "duplicate-line-number",
                    suggestion="Give each line its own step number.",
                )
            elif previous is not None and number < previous:
                if editor:
                    self.add(
                        span,
                        E,
                        f"Step {number} comes after step {previous}: the upload numbers the "
                        "lines in text order, so the numbers written must go up",
                        "line-number-order",
                        suggestion="Move the line to where its number belongs, or jump to a "
                        "*label instead of a step number.",
                    )
                else:
                    self.add(
                        span,
                        W,
                        f"Step {number} comes after step {previous}: the controller runs steps "
                        "in number order, not in text order",
                        "line-number-order",
                        suggestion="Move the line to where its number belongs.",
                    )
            seen.setdefault(number, line.span.line)
            previous = number if previous is None else max(previous, number)

    def labels(self) -> set[str]:
        found: dict[str, int] = {}
        lines = self.program.lines
        for index in self.table.labelled:
            line = lines[index]
            if line.label is None or line.label_span is None:
                continue
            span = line.label_span
            shown = line.label_text or line.label
            if line.label in found:
                self.add(
                    span,
                    E,
                    f"Label *{shown} is already defined on line {found[line.label]}",
                    "duplicate-label",
                    "L4440",
                    "Rename one of the two labels (labels ignore case).",
                )
            else:
                found[line.label] = span.line
            if len(line.label) > MAX_NAME_LENGTH:
                self.add(
                    span,
                    E,
                    f"Label *{shown} is longer than {MAX_NAME_LENGTH} characters",
                    "label-too-long",
                    "L4300",
                    f"Shorten it to {MAX_NAME_LENGTH} characters, e.g. *{shown[:MAX_NAME_LENGTH]}.",
                )
        return set(found)
