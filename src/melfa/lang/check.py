"""The checker: syntax issues from the parser plus static analysis, as Diagnostics.

`check(text, points)` never raises and returns diagnostics sorted by position, each inside
the text. What it finds (rule names are documented in docs/diagnostics.md):

* the parser's issues (at most one per line, more only after THEN/ELSE);
* block structure: FOR/NEXT, WHILE/WEND, IF/ELSE/ENDIF, SELECT/CASE (via `blocks`);
* jumps to labels or step numbers that do not exist, duplicate labels;
* position and joint variables used but defined neither in the program nor in `points`;
* controller limits: 127 characters a step, 123 a DEF list, 8-character names and labels,
  step numbers 1-32767 (ascending, unique), nesting depths, ON GOTO targets, DIM sizes, and
  the ranges of constant arguments (OVRD, hands, pallets, DLY, ERROR);
* type mistakes that are certain (``M1 * P1``, a string assigned to a number…).

Step numbers come in two forms. A program numbered on every non-blank line is in
*controller form*: the controller runs its steps in number order. A program where some lines
have no number is in *editor form* (what `melfa.lang.numbering.strip_numbers` produces: it
keeps the numbers that jumps name): the upload numbers it in text order with
`melfa.lang.numbering.number_lines`, so the numbers written must already ascend (an error
here, a warning in controller form), be unique, and every ``GOTO 120`` must name one of them.
Unnumbered lines are never reported: numbering them is the upload's job.

Every message names things as the student wrote them (``Pa``, not ``PA``), and every finding
with a clear fix carries a `suggestion`: one short imperative sentence ("Write WHILE instead
of WIHLE.").
"""

from __future__ import annotations

import gc
from collections.abc import Callable, Iterable, Sequence, Set
from itertools import chain, compress
from operator import attrgetter, ne
from typing import Any

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.blocks import STRUCTURAL, match_statements
from melfa.lang.check_lines import LineChecks
from melfa.lang.check_names import NameChecks
from melfa.lang.check_routines import RoutineChecks
from melfa.lang.check_v import FunctionBlocks, VChecks, v_program, without_follow_ons
from melfa.lang.check_values import ValueChecks
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.linetable import LineTable
from melfa.lang.model import MAX_NAME_LENGTH, MAX_ON_TARGETS, RANGES, SYSTEM_VARIABLES, Kind
from melfa.lang.reparse import EDITOR
from melfa.lang.symbols import Symbols, target_name
from melfa.lang.typos import suggest

MIN_GUESSED_POINT = 4
"""An undefined point this long or longer gets "Did you mean …?" (``Phom`` → ``Phome``)."""

E, W = Severity.ERROR, Severity.WARNING
# Tuples of enum members, not sets: `in` compares them by identity in C, where a set would
# call Enum's __hash__, a Python function, on every node.
_LOGIC = (A.BinaryOp.AND, A.BinaryOp.OR, A.BinaryOp.XOR)
_NO_NUMBERS_HINT = " (this program has no step numbers)"
_ISSUES = attrgetter("issues")

# Constant arguments with a range: (low, high, what) for the first argument (§4.2–§4.6).
# Keyed by the member's name (`kind._name_`), not the member: no Enum hash per command.
_COMMAND_RANGES: dict[str, tuple[float, float, str]] = {
    kind.name: RANGES[kind.name] for kind in A.CommandKind if kind.name in RANGES
}
_FRAME_KINDS = (A.CommandKind.TOOL, A.CommandKind.BASE)


# Which block family each structural word and each block rule belongs to.
_WORD_FAMILY = {
    "FOR": "FOR",
    "NEXT": "FOR",
    "WHILE": "WHILE",
    "WEND": "WHILE",
    "IF": "IF",
    "ELSE": "IF",
    "ELSEIF": "IF",  # MELFA BASIC V: reported once, its IF block's pairing would only repeat it
    "ENDIF": "IF",
    "SELECT": "SELECT",
    "CASE": "SELECT",
    "DEFAULT": "SELECT",
    "BREAK": "SELECT",
    "END": "SELECT",
}
_RULE_FAMILY = {
    "for-without-next": "FOR",
    "next-without-for": "FOR",
    "next-mismatch": "FOR",
    "while-without-wend": "WHILE",
    "wend-without-while": "WHILE",
    "if-without-endif": "IF",
    "endif-without-if": "IF",
    "else-without-if": "IF",
    "select-without-end": "SELECT",
    "end-select-without-select": "SELECT",
    "case-outside-select": "SELECT",
    "break-outside-block": "SELECT",
}


class _Analyzer(LineChecks, ValueChecks, NameChecks, RoutineChecks, VChecks):
    def __init__(
        self, program: A.Program, points: Iterable[str], repeats: Sequence[int] | None = None
    ) -> None:
        self.program = program
        self.repeats = repeats
        self.points = {p.upper() for p in points}
        self.out: list[Diagnostic] = []
        self.table = LineTable(program)
        self.symbols = Symbols.collect(program, self.points, self.table)
        self.defined = self.symbols.defined
        self.undefined: set[str] = set()  # points already warned about (once per name)
        self.indexed: set[int] = set()  # ids of the Names that have an index: M_IN(8)
        self.unknown_external: set[str] = set()  # misspelt system variables (once per name)
        self.v_named: set[str] = set()  # MELFA BASIC V status variables (once per name)
        self.blocks = FunctionBlocks(program, self.table)
        self.v_functions = self.blocks.names

    # ------------------------------------------------------------------------- passes

    def run(self) -> list[Diagnostic]:
        for issue in chain.from_iterable(map(_ISSUES, self.program.lines)):
            self.add(issue.span, E, issue.message, issue.rule, issue.code, issue.suggestion)
        self.line_limits()
        self.numbering()
        labels = self.labels()
        self.statements(labels)
        self.duplicates()
        self.interrupt_returns()
        self.gotos_leaving_routines()
        broken = self.broken_structure()
        table = self.table
        for problem in match_statements(table.statements, table.having(STRUCTURAL)).problems:
            if _RULE_FAMILY.get(problem.rule) not in broken:
                self.add(
                    problem.span,
                    E,
                    problem.message,
                    problem.rule,
                    problem.code,
                    problem.suggestion,
                )
        found = without_follow_ons(self.out, self.blocks)
        summary = v_program(found)
        if summary is not None:
            found.append(summary)
        return found

    def broken_structure(self) -> set[str]:
        """Block families with an unparsable opener or closer (WIHLE…): their pairing
        findings would only repeat the syntax error, so they are left out."""
        broken: set[str] = set()
        statements = self.table.statements
        for index in self.table.having({A.InvalidStatement}):
            stmt = statements[index]
            assert isinstance(stmt, A.InvalidStatement)
            # The word the student meant: the suggested replacement (END IF → ENDIF), else
            # the first word written (a FOR line with a mistake further on).
            words = stmt.text.upper().split()
            word = stmt.issue.replacement or (words[0] if words else "")
            family = _WORD_FAMILY.get(word.upper())
            if family is not None:
                broken.add(family)
        return broken

    # ----------------------------------------------------------------------- statements

    def statements(self, labels: set[str]) -> None:
        numbers = set(self.table.numbers)
        numbers.discard(None)
        numbered = bool(numbers)
        long_names: set[str] = set()
        # Names `name` has nothing to say about: defined, short, no suffix # and not a
        # system variable (most uses of most names, skipped without a call).
        quiet = {
            name
            for name in self.defined
            if name
            and len(name.rstrip("$%!#")) <= MAX_NAME_LENGTH
            and name[-1:] != "#"
            and not (len(name) > 1 and name[1] == "_")
        }
        no_counters: frozenset[str] = frozenset()
        warned_here: Set[str] = no_counters

        def label_ref(node: A.LabelRef) -> None:
            if node.name not in labels:
                self.undefined_label(node, labels)

        def line_ref(node: A.LineRef) -> None:
            if node.number not in numbers:
                why = "" if numbered else _NO_NUMBERS_HINT
                self.add(
                    node.span,
                    E,
                    f"Step {node.number} does not exist{why}",
                    "undefined-line",
                    "L4230",
                    "Put a *label on the line to jump to, and jump to the label.",
                )

        checks: dict[type, Callable[[Any], None]] = {
            A.LabelRef: label_ref,
            A.LineRef: line_ref,
            **{cls: check.__get__(self) for cls, check in _SPECIFIC.items()},
        }
        # Node class -> (its fields that hold nodes, its check or None); a leaf with no
        # check of its own (a number, a string) is left out.
        plans = {
            cls: (fields, checks.get(cls))
            for cls, fields in A.CHILD_FIELDS.items()
            if fields or cls in checks
        }
        number, name_class = A.Number, A.Name
        # A line written exactly like an earlier one that got no finding and changed no
        # "once per name" set gets none either: those sets only grow, and only keep findings
        # out. Such a line's walk is skipped (real programs repeat lines: HOPEN 1, RETURN).
        repeats = self.repeats
        repeated = _repeated(repeats)  # the lines some later line is written like
        quiet_lines: set[int] = set()
        said = self.out, long_names, self.undefined, self.unknown_external, self.v_named
        stack: list[Any] = []  # the nodes of a line still to visit
        pop, push = stack.pop, stack.append
        for index, stmt in enumerate(self.table.statements):
            if stmt is None or type(stmt) is A.InvalidStatement:
                continue
            if repeats is not None:
                first = repeats[index]
                if first != index and first in quiet_lines:
                    continue
            counting = index in repeated
            if counting:
                before = sum(map(len, said))
            # NEXT's counters are not uses: FOR already defined them (or blocks reports it).
            warned_here = {c.name for c in stmt.counters} if type(stmt) is A.Next else no_counters
            # `A.walk(stmt)`, inline, each node checked as it is reached: the nodes in the
            # same order (the first use of a name is the one reported).
            push(stmt)
            while stack:
                node = pop()
                cls = type(node)
                if cls is name_class:  # the commonest node with a check: tested first, inline
                    if node.name not in quiet:
                        self.name(node, long_names, warned_here)
                    continue
                plan = plans.get(cls)
                if plan is None:  # a tuple of nodes, or a leaf with nothing to check
                    if cls is tuple:
                        stack.extend(node)
                    continue
                fields, check = plan
                for field in fields:
                    value = getattr(node, field)
                    if value is not None and type(value) is not number:
                        push(value)
                if check is not None:
                    check(node)
            if counting and sum(map(len, said)) == before:
                quiet_lines.add(index)

    def undefined_label(self, node: A.LabelRef, labels: set[str]) -> None:
        guess = suggest(node.name, labels) if labels else None
        shown = node.written
        if guess is not None:
            defined = next(
                line.label_text or guess for line in self.program.lines if line.label == guess
            )
            hint = f"Write *{defined} instead of *{shown}, or define *{shown}."
            headline = f"Label *{shown} is not defined in this program. Did you mean *{defined}?"
        else:
            hint = f"Define the label with a line *{shown} where the jump should go."
            headline = f"Label *{shown} is not defined in this program"
        self.add(
            node.span,
            W,
            headline,
            "undefined-label",
            "L3600",
            hint,
        )

    def on_jump(self, node: A.OnJump) -> None:
        if len(node.targets) > MAX_ON_TARGETS:
            self.add(
                node.targets[MAX_ON_TARGETS].span.to(node.targets[-1].span),
                E,
                f"ON … {node.kind.value} has {len(node.targets)} destinations; "
                f"the limit is {MAX_ON_TARGETS}",
                "too-many-targets",
                "L3251",
                "Split the choice into two ON statements (the second for the values above "
                f"{MAX_ON_TARGETS}).",
            )

    def name(self, node: A.Name, long_names: set[str], warned_here: Set[str]) -> None:
        name = node.name
        if len(name.rstrip("$%!#")) > MAX_NAME_LENGTH and name not in long_names:
            long_names.add(name)
            self.add(
                node.span,
                E,
                f"Name {node.written} is longer than {MAX_NAME_LENGTH} characters, the limit "
                "of MELFA BASIC IV (longer names are MELFA BASIC V's)",
                "name-too-long",
                "L4300",
                f"Shorten it to {MAX_NAME_LENGTH} characters.",
            )
        if name[-1] == "#" and name not in long_names:
            long_names.add(name)
            self.double_name(node)
        if len(name) > 1 and name[1] == "_":
            if name in SYSTEM_VARIABLES:  # neither V's nor a typo: only its index to check
                self.system_index(node, id(node) in self.indexed)
                return
            if self.v_system_variable(node):
                return
            if name not in self.unknown_external and self.external_name(node):
                self.unknown_external.add(name)
            self.system_index(node, id(node) in self.indexed)
            return
        if name in self.defined or name in warned_here or name in self.undefined:
            return
        vtype = self.symbols.kind_of_name(name)
        if vtype in (Kind.POS, Kind.JNT):
            self.undefined.add(name)
            kind = "Position" if vtype is Kind.POS else "Joint position"
            shown = node.written
            kind_of = self.symbols.kind_of_name
            # P1/P2, Pa/Pb are different points, not typos: only longer names get a guess.
            candidates = (n for n in self.defined if kind_of(n) is vtype)
            guess = suggest(name, candidates) if len(name) >= MIN_GUESSED_POINT else None
            if guess and shown[1:].islower():  # written as Phom: offered as Phome
                guess = guess[0] + guess[1:].lower()
            add = f"add {shown} to the points file, or assign it before use ({shown} = …)."
            self.add(
                node.span,
                W,
                f"{kind} {shown} is not defined" + (f". Did you mean {guess}?" if guess else ""),
                "undefined-point",
                suggestion=f"Write {guess} instead, or {add}" if guess else "A" + add[1:],
                replace=guess,
            )

    def binary(self, node: A.Binary) -> None:
        op = node.op
        if op in _LOGIC:
            return
        kind_of = self.symbols.kind_of
        left, right = kind_of(node.left), kind_of(node.right)
        if (left is Kind.STR or right is Kind.STR) and self.string_arithmetic(node, left, right):
            return
        if op is not A.BinaryOp.MUL and op is not A.BinaryOp.DIV:
            return
        if left is Kind.NUM and right in (Kind.POS, Kind.JNT):
            sign = op.value
            self.add(
                node.span,
                E,
                f"A number {sign} a position is not allowed",
                "type-mismatch",
                "L4390",
                f"Put the position first: {_shown(node.right)} {sign} {_shown(node.left)}."
                if sign == "*"
                else "Divide the position by the number instead (P / M).",
            )

    def assign(self, node: A.Assign) -> None:
        target = node.target
        name = target_name(target).name
        # Each check is called only where it may find something (this runs on every
        # assignment): system variables have a _ second, ACT1 = … starts with ACT.
        if name[1:2] == "_" and self.read_only(node):
            return
        if type(target) is A.Name and name[:3] == "ACT":
            self.act_variable(node)
        if isinstance(target, A.Element):
            tt: Kind | None = Kind.NUM
        else:
            tt = self.symbols.kind_of_name(name)
        vt = self.symbols.kind_of(node.value)
        if node.pulse is not None:
            self.dly_range(node.pulse)
        if tt is Kind.NUM and type(target) is A.Element:
            self.angle_in_degrees(node)
        if tt is None and self.position_in_number(node, vt):
            return
        if tt is None or vt is None or tt is vt:
            return
        if {tt, vt} == {Kind.POS, Kind.JNT}:
            hint = "Convert it with JTOP() or PTOJ()."
        elif tt is Kind.STR:
            hint = "Convert it with STR$()."
        elif vt is Kind.STR:
            hint = "Convert it with VAL()."
        else:
            hint = "Assign it to a variable of the right type (P… position, M… number)."
        self.add(
            node.value.span,
            E,
            f"Cannot assign a {vt.value} to the {tt.value} variable {target_name(target).written}",
            "type-mismatch",
            "L4390",
            hint,
        )

    def move(self, node: A.Move | A.ArcMove | A.ArchMove) -> None:
        """A move target that is certainly a number or a string (``MVS P1.Z``)."""
        targets = node.points if type(node) is A.ArcMove else (node.target,)  # type: ignore[union-attr]
        kind_of = self.symbols.kind_of
        for target in targets:
            vt = kind_of(target) if target is not None else None
            if target is not None and (vt is Kind.NUM or vt is Kind.STR):
                word = "MVA" if type(node) is A.ArchMove else node.kind.value  # type: ignore[union-attr]
                self.add(
                    target.span,
                    E,
                    f"{word} needs a position to move to, found a {vt.value}",
                    "type-mismatch",
                    "L4390",
                    "Change the element in a copy of the position and move to the copy."
                    if isinstance(target, A.Element)
                    else f"Use positions, e.g. {word} P1, P2, P3."
                    if isinstance(node, A.ArcMove)
                    else f"Move to a position variable or constant, e.g. {word} P1.",
                )

    def command(self, node: A.Command) -> None:
        kind = node.kind
        if not node.args or (kind in _FRAME_KINDS and self.v_frame(node)):
            return
        arg = node.args[0]
        if kind is A.CommandKind.DLY:
            if arg is not None:
                self.dly_range(arg)
            return
        limits = _COMMAND_RANGES.get(kind._name_)
        if limits is not None and arg is not None:
            self.range(arg, limits)

    def array_or_system(self, node: A.Index) -> None:
        self.indexed.add(id(node.name))
        if node.name.name not in self.v_functions:  # a V Function's call: named at its block
            self.index(node)

    def wait(self, node: A.Wait) -> None:
        self.v_wait(node)


def _repeated(repeats: Sequence[int] | None) -> set[int]:
    """The lines that a later line repeats (`repeats[i]` is the first line written like
    line i): the only lines whose findings `statements` needs to count."""
    if repeats is None or len(set(repeats)) == len(repeats):
        return set()  # no line written twice
    return set(compress(repeats, map(ne, repeats, range(len(repeats)))))


def _shown(expr: A.Expr) -> str:
    """A short rendering of an operand for a suggestion (names as written)."""
    if isinstance(expr, A.Name):
        return expr.written
    if isinstance(expr, A.Number):
        return expr.text
    if isinstance(expr, A.Index):
        return f"{expr.name.written}(…)"
    return "(…)"


_Check = Callable[["_Analyzer", Any], None]
# The node classes with checks of their own, for the walk in `statements`.
_SPECIFIC: dict[type, _Check] = {
    A.Binary: _Analyzer.binary,
    A.Assign: _Analyzer.assign,
    A.OnJump: _Analyzer.on_jump,
    A.Command: _Analyzer.command,
    A.Move: _Analyzer.move,
    A.ArcMove: _Analyzer.move,
    A.ArchMove: _Analyzer.move,
    A.Pallet: _Analyzer.pallet,
    A.DefPlt: _Analyzer.def_plt,
    A.DefVar: _Analyzer.def_var,
    A.Dim: _Analyzer.dim,
    A.Call: _Analyzer.call,
    A.Index: _Analyzer.array_or_system,
    A.PositionLiteral: _Analyzer.position_literal,
    A.DefAct: _Analyzer.def_act,
    A.ActSet: _Analyzer.act_set,
    A.Wait: _Analyzer.wait,
}


def check_ast(
    program: A.Program, points: Iterable[str] = (), repeats: Sequence[int] | None = None
) -> list[Diagnostic]:
    """Diagnostics for an already parsed program, sorted by position. `repeats` (from
    `melfa.lang.reparse.LineCache.read`) names the lines written exactly like an earlier
    one, which lets the checker skip what it already said nothing about."""
    found = _Analyzer(program, points, repeats).run()
    found.sort(key=lambda d: (d.line, d.column, d.end_line, d.end_column, d.rule))
    return found


def check(text: str, points: Iterable[str] = ()) -> list[Diagnostic]:
    """Check a program; `points` are the names defined in its points file. Never raises.
    Only the lines not seen before are lexed and parsed (`melfa.lang.reparse.EDITOR`).

    >>> [(d.line, d.code, d.message) for d in check("10 MOV P1\\n20 HOPEN\\n", ["P1"])]
    [(2, 'L4220', 'HOPEN needs a hand number (1 to 8), found the end of the line')]
    """
    collecting = gc.isenabled()
    # The tree is acyclic and lives only as long as this call: a garbage collection while it
    # is built would only walk it again (about an eighth of a check, bench/bench_check.py).
    gc.disable()
    try:
        program, repeats = EDITOR.read(text)
        return check_ast(program, points, repeats)
    except Exception as exc:  # a bug of ours must not take the editor down
        return [internal_error(exc)]
    finally:
        if collecting:
            gc.enable()


def internal_error(exc: Exception) -> Diagnostic:
    """What a bug in the checker becomes: a finding, never a traceback."""
    return Diagnostic(
        1,
        1,
        1,
        1,
        Severity.ERROR,
        f"Internal error in melfa's checker (please report it): {exc!r}",
        "internal-error",
    )
