"""Step numbers: take them off for editing, put them back for the controller.

The controller needs a step number on every line (`10 SERVO ON`) [S2 §4.3.4]; students
would rather write without them and jump to labels (thesis §6.5.1). Both directions work
on tokens (`melfa.lang.lexer.tokenize`), so comments, strings and spacing are untouched.

Decisions:

* **Numbering follows the text line.** Line ``i`` (1-based) of the text gets
  ``start + (i - 1) * step``, so with the defaults step 130 is editor line 13, as in the
  thesis editor. Blank lines keep their number slot but stay blank (an empty step means
  nothing to the controller), which makes strip-then-number the identity on a program
  numbered 10, 20, 30, … even when it has blank lines.
* **Stripping keeps the numbers that jumps use.** `strip_numbers` removes a line's number
  unless some ``GOTO``/``GOSUB``/``THEN``/``ELSE``/``ON … GOTO|GOSUB``/``DEF ACT``/
  ``ON COM`` names it; those lines keep theirs, so the stripped text still says where each
  jump goes and nothing is invented (no generated labels that could clash with the user's).
  `number_lines` then maps every old number to the new one and rewrites the references:
  a program numbered 1, 2, 3 with ``GOTO 2`` comes back as ``GOTO 20``.
* **Nothing is guessed.** A reference to a step that does not exist, numbers out of order
  (the controller runs steps in number order, not text order) or a duplicate number is
  reported as a diagnostic; the text is then returned unchanged by `renumber`/`strip` and
  `number_lines`/`strip_numbers` raise `NumberingError`.
"""

from __future__ import annotations

from collections.abc import Iterator

from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.lexer import tokenize
from melfa.lang.record import Record
from melfa.lang.tokens import Token, TokenKind

__all__ = [
    "MAX_LINE_NUMBER",
    "Numbering",
    "NumberingError",
    "NumberingResult",
    "Reference",
    "controller_text",
    "is_numbered",
    "number_lines",
    "number_tokens",
    "references",
    "renumber",
    "source_line",
    "step_lines",
    "strip",
    "strip_numbers",
]

MAX_LINE_NUMBER = 32767
"""Highest step number; above it the controller says L4420 [S3]."""

_JUMP_WORDS = frozenset({"GOTO", "GOSUB"})
_THEN_WORDS = frozenset({"THEN", "ELSE"})
_END_KINDS = frozenset({TokenKind.NEWLINE, TokenKind.EOF})


class NumberingError(ValueError):
    """The program cannot be (un)numbered without changing its meaning."""

    def __init__(self, diagnostics: tuple[Diagnostic, ...]) -> None:
        first = diagnostics[0]
        super().__init__(f"line {first.line}: {first.message}")
        self.diagnostics = diagnostics


class NumberingResult(Record):
    """The new text, or the old one when `diagnostics` hold an error."""

    text: str
    diagnostics: tuple[Diagnostic, ...] = ()

    @property
    def ok(self) -> bool:
        return not any(d.is_error for d in self.diagnostics)


class Reference(Record):
    """A step number used as a jump target; `token` is the INTEGER token."""

    number: int
    token: Token
    keyword: str  # GOTO, GOSUB, THEN or ELSE: the word the list hangs off


class _Line(Record, frozen=False):
    tokens: list[Token]  # all tokens of the text line, NEWLINE/EOF included

    @property
    def number_token(self) -> Token | None:
        first = self.tokens[0]
        return first if first.kind is TokenKind.LINE_NUMBER else None

    @property
    def is_blank(self) -> bool:
        return all(t.kind in _END_KINDS for t in self.tokens)


def _split_lines(tokens: list[Token]) -> list[_Line]:
    lines: list[_Line] = []
    current: list[Token] = []
    for tok in tokens:
        current.append(tok)
        if tok.kind in _END_KINDS:
            lines.append(_Line(current))
            current = []
    return lines


def _references(tokens: list[Token]) -> Iterator[Reference]:
    """Jump references on one line: after GOTO/GOSUB a list ``n, *L, m``, after THEN/ELSE one."""
    n = len(tokens)
    for i, tok in enumerate(tokens):
        if tok.kind is not TokenKind.KEYWORD:
            continue
        word = tok.text.upper()
        if word in _THEN_WORDS:
            nxt = tokens[i + 1] if i + 1 < n else None
            if nxt is not None and nxt.kind is TokenKind.INTEGER:
                yield Reference(int(nxt.text), nxt, word)
        elif word in _JUMP_WORDS:
            j = i + 1
            while j < n and tokens[j].kind in (TokenKind.INTEGER, TokenKind.LABEL):
                if tokens[j].kind is TokenKind.INTEGER:
                    yield Reference(int(tokens[j].text), tokens[j], word)
                if (
                    j + 2 < n
                    and tokens[j + 1].kind is TokenKind.COMMA
                    and tokens[j + 2].kind in (TokenKind.INTEGER, TokenKind.LABEL)
                ):
                    j += 2
                else:
                    break


def references(text: str) -> list[Reference]:
    """Every step number the program jumps to, in text order.

    >>> [(r.keyword, r.number) for r in references("10 ON M1 GOTO 30, *A, 40\\n20 IF M1 THEN 10")]
    [('GOTO', 30), ('GOTO', 40), ('THEN', 10)]
    """
    return [ref for line in _split_lines(tokenize(text)) for ref in _references(line.tokens)]


def _diag(tok: Token, message: str, rule: str, code: str | None, **kw: str) -> Diagnostic:
    return Diagnostic(
        tok.line,
        tok.column,
        tok.end_line,
        tok.end_column,
        Severity.ERROR,
        message,
        rule,
        code,
        kw.get("suggestion"),
    )


def _numbering_problems(lines: list[_Line]) -> list[Diagnostic]:
    """Duplicate or descending step numbers: text order is not execution order."""
    out: list[Diagnostic] = []
    seen: dict[int, int] = {}
    previous: int | None = None
    for index, line in enumerate(lines, start=1):
        tok = line.number_token
        if tok is None:
            continue
        number = int(tok.text)
        if number in seen:
            out.append(
                _diag(
                    tok,
                    f"Step {number} is numbered twice (first on line {seen[number]})",
                    "numbering-duplicate",
                    None,
                    suggestion="Give each step its own number.",
                )
            )
        elif previous is not None and number < previous:
            out.append(
                _diag(
                    tok,
                    f"Step {number} comes after step {previous} in the text; the controller "
                    "runs steps in number order, so renumbering would change the program",
                    "numbering-order",
                    None,
                    suggestion="Move the line to where its number belongs.",
                )
            )
        seen.setdefault(number, index)
        previous = number if previous is None else max(previous, number)
    return out


def _missing_target(ref: Reference, severity: Severity) -> Diagnostic:
    return Diagnostic(
        ref.token.line,
        ref.token.column,
        ref.token.end_line,
        ref.token.end_column,
        severity,
        f"{ref.keyword} {ref.number}: there is no step {ref.number}",
        "numbering-missing-target",
        "L4230",
        f"Put a label (*NAME) on the line to jump to, and write {ref.keyword} *NAME.",
    )


def renumber(text: str, start: int = 10, step: int = 10) -> NumberingResult:
    """Number every line, rewriting jumps to the new numbers (see the module docstring).

    >>> print(renumber("1 MOV P1\\n2 GOTO 1\\n").text, end="")
    10 MOV P1
    20 GOTO 10
    """
    return _renumber(_lines(text), start, step)


def _renumber(lines: list[_Line], start: int, step: int) -> NumberingResult:
    """`renumber` on a program already split into token lines."""
    if start < 1 or step < 1:
        raise ValueError("start and step must be positive")
    problems = _numbering_problems(lines)
    mapping: dict[int, int] = {}
    for index, line in enumerate(lines):
        tok = line.number_token
        if tok is not None:
            mapping.setdefault(int(tok.text), start + index * step)
    last = max((start + i * step for i, line in enumerate(lines) if not line.is_blank), default=0)
    if last > MAX_LINE_NUMBER:
        first_over = next(i for i, line in enumerate(lines) if start + i * step > MAX_LINE_NUMBER)
        tok = lines[first_over].tokens[0]
        problems.append(
            _diag(
                tok,
                f"Numbering from {start} in steps of {step} reaches {last}; step numbers stop "
                f"at {MAX_LINE_NUMBER}",
                "numbering-overflow",
                "L4420",
                suggestion="Use a smaller step.",
            )
        )
    replacements: dict[int, str] = {}  # id of a token -> its new text
    for line in lines:
        for ref in _references(line.tokens):
            if ref.number in mapping:
                replacements[id(ref.token)] = str(mapping[ref.number])
            else:
                problems.append(_missing_target(ref, Severity.ERROR))
    if problems:
        return NumberingResult(_joined(lines), tuple(sorted(problems, key=_position)))
    parts: list[str] = []
    for index, line in enumerate(lines):
        number = start + index * step
        numbered = line.number_token is not None
        if not numbered and not line.is_blank:
            parts.append(f"{number} ")
        for tok in line.tokens:
            new = str(number) if numbered and tok is line.tokens[0] else replacements.get(id(tok))
            parts.append(tok.prefix + (tok.text if new is None else new))
    return NumberingResult("".join(parts))


def strip(text: str) -> NumberingResult:
    """Remove step numbers, keeping those that jumps name (see the module docstring).

    >>> print(strip("10 MOV P1\\n20 HOPEN 1\\n30 GOTO 10\\n").text, end="")
    10 MOV P1
    HOPEN 1
    GOTO 10
    """
    lines = _split_lines(tokenize(text))
    problems = _numbering_problems(lines)
    existing = {int(t.text) for line in lines if (t := line.number_token) is not None}
    targets: set[int] = set()
    for line in lines:
        for ref in _references(line.tokens):
            targets.add(ref.number)
            if ref.number not in existing:
                # Already dangling; stripping does not make it worse, but say so.
                problems.append(_missing_target(ref, Severity.WARNING))
    if any(d.is_error for d in problems):
        return NumberingResult(text, tuple(sorted(problems, key=_position)))
    parts: list[str] = []
    for line in lines:
        tok = line.number_token
        rest = line.tokens
        if tok is not None and int(tok.text) not in targets:
            # Drop the number with the whitespace before it and one separator after it.
            nxt = line.tokens[1]
            parts.append(nxt.prefix[1:] + nxt.text)
            rest = line.tokens[2:]
        parts.extend(t.prefix + t.text for t in rest)
    return NumberingResult("".join(parts), tuple(sorted(problems, key=_position)))


def _position(d: Diagnostic) -> tuple[int, int]:
    return (d.line, d.column)


def number_lines(text: str, start: int = 10, step: int = 10) -> str:
    """`renumber`, raising `NumberingError` when it cannot be done safely.

    >>> number_lines("SERVO ON\\n\\n*LOOP\\nGOTO *LOOP")
    '10 SERVO ON\\n\\n30 *LOOP\\n40 GOTO *LOOP'
    """
    result = renumber(text, start, step)
    if not result.ok:
        raise NumberingError(result.diagnostics)
    return result.text


def strip_numbers(text: str) -> str:
    """`strip`, raising `NumberingError` when it cannot be done safely.

    >>> strip_numbers("10 SERVO ON\\n20 END")
    'SERVO ON\\nEND'
    """
    result = strip(text)
    if not result.ok:
        raise NumberingError(result.diagnostics)
    return result.text


def is_numbered(text: str) -> bool:
    """Whether every non-blank line already starts with a step number (sent as it is).

    >>> is_numbered("10 MOV P1\\n\\n20 END"), is_numbered("10 MOV P1\\nEND")
    (True, False)
    """
    return _all_numbered(_lines(text))


def controller_text(text: str, start: int = 10, step: int = 10) -> str:
    """The program as the controller gets it (`number_tokens`'s text): a numbered text as it
    is, any other numbered; `NumberingError` when that cannot be done safely."""
    numbering = number_tokens(tokenize(text), start, step)
    if numbering.text is None:
        raise NumberingError(numbering.diagnostics)
    return numbering.text


def step_lines(text: str, start: int = 10, step: int = 10) -> dict[int, int]:
    """Step number the controller reports -> 1-based line of `text` (the user's own text,
    numbered or not), following `controller_text`. The one home for this mapping: the
    robot's current line and the debugger's current statement both go through it.

    >>> step_lines("SERVO ON\\n\\n*LOOP\\nGOTO *LOOP")
    {10: 1, 30: 3, 40: 4}
    >>> step_lines("5 MOV P1\\n7 END")
    {5: 1, 7: 2}
    """
    lines = _lines(text)
    return _step_lines(lines, _all_numbered(lines), start, step)


def _step_lines(lines: list[_Line], numbered: bool, start: int, step: int) -> dict[int, int]:
    mapping: dict[int, int] = {}
    for index, line in enumerate(lines):
        if line.is_blank:
            continue
        tok = line.number_token
        number = int(tok.text) if numbered and tok is not None else start + index * step
        mapping.setdefault(number, index + 1)
    return mapping


def source_line(text: str, step_number: int | None) -> int | None:
    """The line of `text` the controller's step `step_number` came from (None if none).

    >>> source_line("SERVO ON\\nMOV P1", 20), source_line("SERVO ON", 99)
    (2, None)
    """
    if step_number is None:
        return None
    return step_lines(text).get(step_number)


def _all_numbered(lines: list[_Line]) -> bool:
    return all(line.number_token is not None or line.is_blank for line in lines)


def _lines(text: str) -> list[_Line]:
    return _split_lines(tokenize(text))


def _joined(lines: list[_Line]) -> str:
    """The text back from its tokens (the lexer is lossless)."""
    return "".join(t.prefix + t.text for line in lines for t in line.tokens)


def _spaced(lines: list[_Line]) -> str:
    """A numbered program as sent: unchanged, except that a step number glued to its
    statement (``3END``, which the lexer and the checker read as step 3) gets a space, as
    the controller's own listings write it (the virtual controller refuses ``3END``)."""
    parts: list[str] = []
    for line in lines:
        number = line.number_token
        for tok in line.tokens:
            glued = (
                number is not None
                and tok is line.tokens[1]
                and not tok.prefix
                and tok.kind not in _END_KINDS
            )
            parts.append((" " if glued else tok.prefix) + tok.text)
    return "".join(parts)


class Numbering(Record):
    """How a program goes to the controller, decided once from its tokens (the upload
    plan's, `melfa.lang.plan`): whether it was numbered already (then it is sent as it is),
    the text to send (None when it cannot be numbered without changing its meaning, with
    `diagnostics` saying why; ``3END`` is sent as ``3 END``) and which line of the user's
    text each step number is."""

    numbered: bool
    text: str | None
    step_lines: dict[int, int]
    diagnostics: tuple[Diagnostic, ...] = ()


def number_tokens(tokens: list[Token], start: int = 10, step: int = 10) -> Numbering:
    """`controller_text` and `step_lines` at once, on tokens already made.

    >>> n = number_tokens(tokenize("1 MOV P1\\n2 GOTO 1\\n3END"))
    >>> n.numbered, n.step_lines
    (True, {1: 1, 2: 2, 3: 3})
    >>> number_tokens(tokenize("MOV P1\\nEND")).text
    '10 MOV P1\\n20 END'
    """
    lines = _split_lines(tokens)
    numbered = _all_numbered(lines)
    mapping = _step_lines(lines, numbered, start, step)
    if numbered:
        return Numbering(True, _spaced(lines), mapping)
    result = _renumber(lines, start, step)
    if not result.ok:
        return Numbering(False, None, mapping, result.diagnostics)
    return Numbering(False, result.text, mapping)
