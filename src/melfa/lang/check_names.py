"""Checks that need the symbol tables: functions, arrays, system variables, interrupts, types.

A mixin of the checker (`melfa.lang.check`): each method looks at one kind of tree node (or
the whole program, for interrupt routines) and reports through `add`. What exists and how
it is called comes from the language model (`melfa.lang.model`); what the program defines
comes from `melfa.lang.symbols`. Errors where the controller would refuse the program or
fail at run time for certain; warnings where a mistake is very likely. Sections (§) are
those of melfa-basic-iv.md.
"""

from __future__ import annotations

import functools
import math

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.diagnostics import Severity
from melfa.lang.model import (
    FUNCTIONS,
    MAX_JOINT_ELEMENTS,
    MAX_POSITION_ELEMENTS,
    RANGES,
    SYSTEM_VARIABLES,
    Index,
    Kind,
    is_external,
)
from melfa.lang.reporter import Reporter
from melfa.lang.symbols import Symbols, target_name
from melfa.lang.typos import osa_distance, suggest

E, W = Severity.ERROR, Severity.WARNING
_ARITHMETIC = frozenset(
    {A.BinaryOp.POW, A.BinaryOp.MUL, A.BinaryOp.DIV, A.BinaryOp.IDIV, A.BinaryOp.MOD,
     A.BinaryOp.ADD, A.BinaryOp.SUB, A.BinaryOp.SHL, A.BinaryOp.SHR}
)  # fmt: skip
_SYSTEM_NAMES = tuple(SYSTEM_VARIABLES)
_FUNCTION_NAMES = tuple(FUNCTIONS)
_ANGLES = (A.ElementKind.A, A.ElementKind.B, A.ElementKind.C)  # a tuple: no Enum hash
_FULL_TURN = 2 * math.pi
_EXAMPLE = {Kind.NUM: "M1", Kind.STR: "C1$", Kind.POS: "P1", Kind.JNT: "J1"}


@functools.cache
def _close_system_variable(name: str) -> str | None:
    """The system variable `name` is one edit away from (same type letter), else None.

    Stricter than the keyword typo rule: external variables of one's own (``M_COUNT``,
    ``M_01``) are legal names and must not be called typos.
    """
    best = None
    for candidate in _SYSTEM_NAMES:
        close = candidate[0] == name[0] and osa_distance(name, candidate, 2) == 1
        if close and (best is None or candidate < best):
            best = candidate
    return best


def _a(kind: Kind) -> str:
    return f"a {kind.value}"


class NameChecks(Reporter):
    """The checks on names and calls; mixed into the checker's analyser."""

    program: A.Program
    symbols: Symbols

    # ------------------------------------------------------------------ system variables

    def external_name(self, node: A.Name) -> bool:
        """A name with ``_`` as 2nd character that is not a system variable but is close to
        one (``M_INN``): as written it is an external variable, almost surely a typo (§6).
        True when reported."""
        name = node.name
        symbols = self.symbols
        if name in SYSTEM_VARIABLES or name in symbols.arrays or name in symbols.declared:
            return False
        guess = _close_system_variable(name)
        if guess is None:
            return False
        self.add(
            node.span,
            W,
            f"{node.written} is not a system variable (as written it is an external "
            f"variable of your own). Did you mean {guess}?",
            "unknown-system-variable",
            suggestion=f"Write {guess} instead of {node.written}.",
        )
        return True

    def system_index(self, node: A.Name, indexed: bool) -> None:
        """``M_IN`` with no number in parentheses (§6)."""
        var = SYSTEM_VARIABLES.get(node.name)
        if var is not None and var.index is Index.REQUIRED and not indexed:
            self.add(
                node.span,
                E,
                f"{node.written} needs a number in parentheses",
                "system-variable-index",
                "L4220",
                f"Write {node.written}(n), e.g. {node.written}(8).",
            )

    def read_only(self, node: A.Assign) -> bool:
        """Assigning a status variable the controller only lets programs read (§6)."""
        name = target_name(node.target)
        var = SYSTEM_VARIABLES.get(name.name)
        if var is None or var.assignable:
            return False
        self.add(
            name.span,
            E,
            f"{name.written} is a system variable that programs can only read",
            "read-only-system-variable",
            "L4390",
            f"Assign your own variable instead, e.g. {_EXAMPLE[var.kind]} = …",
        )
        return True

    def position_in_number(self, node: A.Assign, value_kind: Kind | None) -> bool:
        """``FP = (…)(7,0)`` with no DEF POS FP: FP is a number (§2.1), and storing a
        position in it stops the program with L4390 (the simulator does). True if reported."""
        target = node.target
        if value_kind not in (Kind.POS, Kind.JNT) or not isinstance(target, A.Name):
            return False
        name = target.name
        if name in self.symbols.declared or is_external(name) or name[:1] in ("P", "J"):
            return False
        kind, letter, word = (
            ("position", "P", "POS") if value_kind is Kind.POS else ("joint position", "J", "JNT")
        )
        self.add(
            node.value.span,
            E,
            f"{target.written} is a number (its name does not start with {letter} and no "
            f"DEF {word} declares it), so it cannot hold a {kind}",
            "position-in-number",
            "L4390",
            f"Declare it first with DEF {word} {target.written}, or give it a name that "
            f"starts with {letter}.",
        )
        return True

    def angle_in_degrees(self, node: A.Assign) -> None:
        """``PH1.C = 70``: A, B and C hold radians in a program (§2.3 [S2 p.145 note 1]); a
        constant beyond a full turn was surely meant in degrees."""
        target = node.target
        if not isinstance(target, A.Element) or target.element not in _ANGLES:
            return
        value = A.constant_number(node.value)
        if value is None or abs(value) <= _FULL_TURN:
            return
        shown = node.value.span
        self.add(
            shown,
            W,
            f"{target.element.value} holds radians in a program; {value:g} rad is "
            f"{abs(value) / _FULL_TURN:.1f} turns, so this looks like degrees",
            "angle-in-degrees",
            suggestion=f"Convert it: RAD({value:g}) gives {math.radians(value):.4f} rad.",
        )

    def act_variable(self, node: A.Assign) -> None:
        """``ACT1 = 1``: without the space, ACT1 is a variable, and interrupt 1 stays off
        ("ACT1 without a space is parsed as a variable name", §4.6 [S1 ACT])."""
        target = node.target
        if not isinstance(target, A.Name) or target.name in self.symbols.declared:
            return
        name = target.name
        if name.startswith("ACT") and name[3:].isdigit():
            number = name[3:]
            self.add(
                target.span,
                W,
                f"{target.written} is a variable named {target.written}, not the interrupt "
                f"switch ACT {number}: interrupt {number} is not enabled",
                "act-without-space",
                suggestion=f"Write ACT {number} = … with a space to switch interrupt {number}.",
            )

    def double_name(self, node: A.Name) -> None:
        """``MTIMEOUT#``: V's double-precision suffix (§2.1 [S2 §4.3.6]), said once a name."""
        bare = node.written[:-1]
        self.add(
            node.span,
            E,
            f"The # of {node.written} marks a double-precision variable in MELFA BASIC V; "
            "MELFA BASIC IV declares one with DEF DOUBLE",
            "melfa-basic-v",
            "L4220",
            f"Write {bare} and declare it with DEF DOUBLE {bare}.",
        )

    # -------------------------------------------------------------------- calls, arrays

    def call(self, node: A.Call) -> None:
        if node.user:
            self.user_call(node)
            return
        spec = FUNCTIONS.get(node.name)
        if spec is None:
            return
        count = len(node.args)
        if not spec.min_args <= count <= spec.max_args:
            self.add(
                node.span,
                E,
                f"{node.name} takes {spec.arity_text} argument"
                f"{'' if spec.arity_text == '1' else 's'}, found {count}",
                "wrong-argument-count",
                "L4220",
                f"Write it as {spec.usage}.",
            )
            return
        for i, arg in enumerate(node.args):
            want = spec.param(i)
            got = self.symbols.kind_of(arg)
            if want is None or got is None or got is want:
                continue
            fix = {
                (Kind.NUM, Kind.STR): f"Convert it with VAL(), e.g. {node.name}(VAL(…)).",
                (Kind.STR, Kind.NUM): f"Convert it with STR$(), e.g. {node.name}(STR$(…)).",
                (Kind.POS, Kind.JNT): "Convert it with JTOP().",
                (Kind.JNT, Kind.POS): "Convert it with PTOJ().",
            }.get((want, got), f"Give {_a(want)}, e.g. {_EXAMPLE[want]}.")
            self.add(
                arg.span,
                E,
                f"{node.name} needs {_a(want)} here, found {_a(got)}",
                "type-mismatch",
                "L4390",
                fix,
            )

    def user_call(self, node: A.Call) -> None:
        """``FNMAX(…)``: defined by a DEF FN in this program, before the call (§4.6)."""
        found = self.symbols.functions.get(node.name)
        shown = node.name
        if found is None:
            self.add(
                node.span,
                E,
                f"Function {shown} is not defined in this program",
                "undefined-function",
                suggestion=f"Define it first with DEF {shown}(…) = …",
            )
            return
        made, params = found
        if made.name.span.line > node.span.line:
            self.add(
                node.span,
                W,
                f"{shown} is used before its DEF {shown} (line {made.name.span.line}); "
                "the DEF must run first",
                "function-before-def",
                suggestion=f"Move the DEF {shown} line above its first use.",
            )
        if len(node.args) != params:
            self.add(
                node.span,
                E,
                f"{shown} takes {params} argument{'' if params == 1 else 's'} "
                f"(DEF on line {made.name.span.line}), found {len(node.args)}",
                "wrong-argument-count",
                "L4220",
                f"Give {shown} the {params} argument{'' if params == 1 else 's'} of its DEF.",
            )

    def index(self, node: A.Index) -> None:
        """``A(3)``: an array must be DIMmed (§3); system variables take their index."""
        name = node.name
        if name.name in SYSTEM_VARIABLES or name.name in self.symbols.declared:
            return
        array = self.symbols.arrays.get(name.name)
        if array is None:
            if is_external(name.name):
                return  # an external array, DIMmed by another program (or a typo: reported)
            guess = suggest(name.name, _FUNCTION_NAMES)
            hint = (
                f"Write {guess} if you meant the function, or add DIM {name.written}(10)."
                if guess is not None
                else f"Add DIM {name.written}(10) (the size it needs) before its first use."
            )
            self.add(
                name.span,
                E,
                f"{name.written}( ) is used as an array, but there is no DIM {name.written}",
                "array-without-dim",
                "L4370",
                hint,
            )
            return
        made, dims = array
        if made.name.span.line > name.span.line:
            self.add(
                name.span,
                W,
                f"Array {name.written} is used before its DIM (line {made.name.span.line})",
                "array-before-dim",
                suggestion=f"Move DIM {made.name.written} above its first use.",
            )
        if len(node.args) != dims:
            self.add(
                node.span,
                E,
                f"{name.written} has {dims} dimension{'' if dims == 1 else 's'} "
                f"(DIM on line {made.name.span.line}), found {len(node.args)} index"
                f"{'' if len(node.args) == 1 else 'es'}",
                "array-dimensions",
                "L4370",
                f"Give {dims} index{'' if dims == 1 else 'es'}, as in its DIM.",
            )

    def duplicates(self) -> None:
        """The same name declared twice (DEF, DIM, DEF FN): L4350 (§2.1)."""
        for name, first, how in self.symbols.duplicates:
            self.add(
                name.span,
                E,
                f"{name.written} is already declared on line {first.name.span.line} "
                f"({how} declares a name once)",
                "duplicate-definition",
                "L4350",
                f"Remove this declaration of {name.written}, or rename one of the two.",
            )

    # --------------------------------------------------------------------------- values

    def position_literal(self, node: A.PositionLiteral) -> None:
        """A constant with more than 8 elements or more than 2 flags (§2.2)."""
        limit = MAX_POSITION_ELEMENTS if node.flags is not None else MAX_JOINT_ELEMENTS
        if len(node.elements) > limit:
            self.add(
                node.span,
                E,
                f"A position constant has at most {limit} elements "
                "(X, Y, Z, A, B, C, L1, L2 or J1…J8), found "
                f"{len(node.elements)}",
                "position-elements",
                "L3860",
                "Remove the extra values.",
            )
        if node.flags is not None and len(node.flags) > 2:
            self.add(
                node.span,
                E,
                f"Structure flags are two numbers (FL1, FL2), found {len(node.flags)}",
                "position-elements",
                "L3860",
                "Write the flags as (FL1, FL2), e.g. (7, 0).",
            )

    def string_arithmetic(self, node: A.Binary, left: Kind | None, right: Kind | None) -> bool:
        """``C1$ * 2``, ``"5" + 1``: a string where a number is needed (§2.4); `left` and
        `right` are the operands' kinds. True when reported."""
        if left is None or right is None or (left is not Kind.STR and right is not Kind.STR):
            return False
        op = node.op
        if op not in _ARITHMETIC and not op.is_comparison:
            return False
        if left is right and (op is A.BinaryOp.ADD or op.is_comparison):
            return False  # joining or comparing two strings
        other = right if left is Kind.STR else left
        if other is Kind.STR:
            message = f"Strings cannot be combined with {op.value}; only + joins them"
            fix = "Join strings with +, or convert them with VAL() to compute."
        else:
            message = f"A string and {_a(other)} cannot be combined with {op.value}"
            fix = (
                "Convert the string with VAL() (or the number with STR$())."
                if other is Kind.NUM
                else "Use a number or a position element (P1.X) instead of the string."
            )
        self.add(node.span, E, message, "type-mismatch", "L4390", fix)
        return True

    # ----------------------------------------------------------------------- interrupts

    def def_act(self, node: A.DefAct) -> None:
        self.range(node.priority, RANGES["ACT"])

    def act_set(self, node: A.ActSet) -> None:
        _, high, what = RANGES["ACT"]
        self.range(node.number, (0, high, what + " (ACT 0 switches them all)"))

    def range(self, arg: A.Expr, limits: tuple[float, float, str]) -> None:
        raise NotImplementedError  # the checker's
