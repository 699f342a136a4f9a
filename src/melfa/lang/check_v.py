"""MELFA BASIC V in a MELFA BASIC IV program: each construct named once, and nothing after it.

Most programs found online are MELFA BASIC V (CR750/CR800-era controllers); the CR2B-574
runs IV (melfa-basic-iv.md §0). A V construct gets one finding, `melfa-basic-v`, that says
it is V and how to write it in IV, or that IV has no way ("not available in IV"). What only
follows from it is left out: the lines of a ``Function … FEnd`` block and the calls of its
function (which would read as arrays without DIM). When most of a file's errors are V's, one
more finding says the file looks like a V program.

A mixin of the checker (`melfa.lang.check`), like `melfa.lang.check_names`. Sections (§) are
those of melfa-basic-iv.md; [S…] its sources.
"""

from __future__ import annotations

import re

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.linetable import LineTable
from melfa.lang.model import (
    SYSTEM_VARIABLES,
    V_SYSTEM_PREFIXES,
    V_SYSTEM_VARIABLES,
    Kind,
)
from melfa.lang.reporter import Reporter
from melfa.lang.symbols import Symbols

E, W = Severity.ERROR, Severity.WARNING
V_RULE = "melfa-basic-v"
# Findings that say "this is V's": constructs, and names or labels longer than IV's 8.
_V_RULES = frozenset({V_RULE, "name-too-long", "label-too-long"})
_FUNCTION = re.compile(r"FUNCTION\s+(?:[A-Z]+\s+)?([A-Z][A-Z0-9_]*)", re.IGNORECASE)
_FRAMES = {
    A.CommandKind.TOOL: (
        "a numbered tool frame",
        "Give TOOL the tool's data, e.g. TOOL (0, 0, 100, 0, 0, 0), or TOOL P_NTOOL for none.",
    ),
    A.CommandKind.BASE: (
        "a numbered work coordinate",
        "Give BASE the base's data, e.g. BASE (0, 0, 0, 0, 0, 0), or BASE P_NBASE for none.",
    ),
}


class FunctionBlocks:
    """The ``Function … FEnd`` blocks of a program (V): their names and their lines."""

    def __init__(self, program: A.Program, table: LineTable | None = None) -> None:
        names: set[str] = set()
        inside: set[int] = set()  # 1-based lines after a Function, up to its FEnd
        start: int | None = None
        table = table or LineTable(program)
        # A block starts with a line the parser refused: none, no block (most programs).
        lines = program.lines if table.has(A.InvalidStatement) else ()
        for line in lines:
            stmt = line.statement
            if not isinstance(stmt, A.InvalidStatement) or stmt.issue.rule != V_RULE:
                if start is not None:
                    inside.add(line.span.line)
                continue
            word = stmt.text.split(None, 1)[0].upper() if stmt.text.strip() else ""
            if word == "FUNCTION":
                found = _FUNCTION.match(stmt.text)
                if found:
                    names.add(found.group(1).upper())
                start = line.span.line
            elif start is not None:
                inside.add(line.span.line)
                if word == "FEND":
                    start = None
        self.names = frozenset(names)
        self.lines = frozenset(inside)


class VChecks(Reporter):
    """The checks that name MELFA BASIC V; mixed into the checker's analyser."""

    symbols: Symbols
    v_functions: frozenset[str] = frozenset()
    v_named: set[str]  # V system variables already reported (once per name)

    def v_system_variable(self, node: A.Name) -> bool:
        """``M_PI``, ``C_COM(1)``, ``P_FsCurD``: V's status variables (§6, [S16] lists),
        named once per name. True when the name is one of them."""
        name = node.name
        if name in SYSTEM_VARIABLES:
            return False
        family = ""
        if name in V_SYSTEM_VARIABLES:
            in_iv = V_SYSTEM_VARIABLES[name]
        elif name.startswith(V_SYSTEM_PREFIXES):
            in_iv, family = None, "P_FS"  # the force-sensor family is named once: P_Fs…, M_Fs…
        else:
            return False
        key = family or name
        if key not in self.v_named:
            self.v_named.add(key)
            what = (
                f"{node.written} (like every P_Fs…, M_Fs… name) is a force-sensor status variable"
                if family
                else f"{node.written} is a status variable"
            )
            self.add(
                node.span,
                E,
                f"{what} of MELFA BASIC V; MELFA BASIC IV does not have it (as written it is "
                "an external variable nothing sets)",
                V_RULE,
                "L4220",
                in_iv or "Not available in IV: MELFA BASIC IV has no equivalent.",
            )
        return True

    def v_frame(self, node: A.Command) -> bool:
        """``TOOL 1``, ``BASE 2``: V's numbered frames; IV's TOOL and BASE take a position
        (§4.4, [S1 TOOL, BASE]; V: [S10-TOOLRELATIVE], [S11]). True when reported."""
        what = _FRAMES.get(node.kind)
        if what is None or not node.args or node.args[0] is None:
            return False
        arg = node.args[0]
        if self.symbols.kind_of(arg) is not Kind.NUM:
            return False
        word = node.kind.value
        self.add(
            arg.span,
            E,
            f"{word} with a number ({what[0]}) is MELFA BASIC V; MELFA BASIC IV's {word} "
            "takes a position",
            V_RULE,
            "L4220",
            what[1],
        )
        return True

    def v_wait(self, node: A.Wait) -> None:
        """IV waits for a variable to equal a constant, ``WAIT M_IN(1)=1`` [S1 WAIT]; any
        other condition (``WAIT M_IN8(100) <> 0``) is V's general WAIT (§4.5, [S15])."""
        cond = node.condition
        if (
            isinstance(cond, A.Binary)
            and cond.op is A.BinaryOp.EQ
            and isinstance(cond.left, A.Name | A.Index | A.Element)
            and A.constant_number(cond.right) is not None
        ):
            return
        self.add(
            cond.span,
            E,
            "WAIT with a general condition is MELFA BASIC V; MELFA BASIC IV's WAIT waits for "
            "a variable to equal a constant (WAIT M_IN(1) = 1)",
            V_RULE,
            "L4220",
            "Wait in a loop instead: a line *LWAIT, then IF NOT (condition) THEN GOTO *LWAIT.",
        )


def without_follow_ons(found: list[Diagnostic], blocks: FunctionBlocks) -> list[Diagnostic]:
    """Each V construct once: the findings on a ``Function … FEnd`` block's lines are left
    out, and a construct used again (``Fsc`` on six lines) is named at its first use, with
    the lines of the others."""
    if blocks.lines:
        found = [d for d in found if d.line not in blocks.lines]
    first: dict[str, int] = {}
    others: dict[int, list[int]] = {}
    kept: list[Diagnostic] = []
    for d in sorted(found, key=lambda d: (d.line, d.column)):
        if d.rule == V_RULE:
            at = first.get(d.message)
            if at is not None:
                others[at].append(d.line)
                continue
            first[d.message] = len(kept)
            others[len(kept)] = []
        kept.append(d)
    for at, lines in others.items():
        if lines:
            d = kept[at]
            shown = ", ".join(map(str, lines[:5])) + (", …" if len(lines) > 5 else "")
            kept[at] = Diagnostic(
                d.line, d.column, d.end_line, d.end_column, d.severity,
                f"{d.message} (also on line{'s' if len(lines) > 1 else ''} {shown})",
                d.rule, d.code, d.suggestion,
            )  # fmt: skip
    return kept


def v_program(found: list[Diagnostic]) -> Diagnostic | None:
    """One "this looks like a MELFA BASIC V program", when most errors are V's."""
    errors = [d for d in found if d.severity is E]
    v = [d for d in errors if d.rule in _V_RULES]
    if len(v) < 2 or 2 * len(v) <= len(errors):
        return None
    first = min(v, key=lambda d: (d.line, d.column))
    return Diagnostic(
        first.line,
        first.column,
        first.end_line,
        first.end_column,
        W,
        f"This looks like a MELFA BASIC V program: {len(v)} of its {len(errors)} errors are "
        "MELFA BASIC V (newer controllers, CR750/CR800); the CR2B-574 runs MELFA BASIC IV",
        "melfa-basic-v-program",
        None,
        "Rewrite each V construct the IV way its finding gives, or run the program on a "
        "controller with MELFA BASIC V.",
    )
