"""Block matching, done once at load: which NEXT closes which FOR, where an IF's ELSE and
ENDIF are, which CASEs belong to a SELECT, what a BREAK leaves.

Kept apart from the statement compilers because it is pure (statements in, index tables
out) and every flow statement reads its result. A structure error is recorded against the
step (`Structure.problems`), not raised: like the controller, a program with a NEXT
without FOR runs until it reaches that line.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from melfa.lang import ast
from melfa.sim.interp import errors


@dataclass(slots=True)
class Structure:
    """Block matching results, by step index."""

    for_next: dict[int, tuple[int, int]] = field(default_factory=dict)  # for -> (next, k)
    while_wend: dict[int, int] = field(default_factory=dict)
    wend_while: dict[int, int] = field(default_factory=dict)
    if_else: dict[int, int | None] = field(default_factory=dict)
    if_end: dict[int, int] = field(default_factory=dict)
    else_end: dict[int, int] = field(default_factory=dict)
    select_cases: dict[int, list[int]] = field(default_factory=dict)
    select_end: dict[int, int] = field(default_factory=dict)
    breaks: dict[int, tuple[str, int]] = field(default_factory=dict)  # -> (kind, opener)
    problems: dict[int, tuple[int, str]] = field(default_factory=dict)


def match_blocks(stmts: list[ast.Statement | None]) -> Structure:
    """Match the block statements of a program (by step index)."""
    st = Structure()
    stack: list[tuple[str, int]] = []
    for i, s in enumerate(stmts):
        if isinstance(s, ast.For):
            stack.append(("FOR", i))
        elif isinstance(s, ast.While):
            stack.append(("WHILE", i))
        elif isinstance(s, ast.If) and s.is_block:
            stack.append(("IF", i))
            st.if_else[i] = None
        elif isinstance(s, ast.Select):
            stack.append(("SELECT", i))
            st.select_cases[i] = []
        elif isinstance(s, ast.Next):
            for k in range(max(1, len(s.counters))):
                if not stack or stack[-1][0] != "FOR":
                    st.problems[i] = (errors.FOR_NEXT_UNMATCH, "NEXT without FOR")
                    break
                st.for_next[stack.pop()[1]] = (i, k)
        elif isinstance(s, ast.Wend):
            if not stack or stack[-1][0] != "WHILE":
                st.problems[i] = (errors.WHILE_WEND_UNMATCH, "WEND without WHILE")
                continue
            w = stack.pop()[1]
            st.while_wend[w] = i
            st.wend_while[i] = w
        elif isinstance(s, ast.Else):
            if not stack or stack[-1][0] != "IF" or st.if_else[stack[-1][1]] is not None:
                st.problems[i] = (errors.IF_ELSE_UNMATCH, "ELSE without a block IF")
                continue
            st.if_else[stack[-1][1]] = i
        elif isinstance(s, ast.EndIf):
            if not stack or stack[-1][0] != "IF":
                st.problems[i] = (errors.IF_ENDIF_UNMATCH, "ENDIF without a block IF")
                continue
            opener = stack.pop()[1]
            st.if_end[opener] = i
            els = st.if_else[opener]
            if els is not None:
                st.else_end[els] = i
        elif isinstance(s, ast.Case | ast.Default):
            sel = next((j for kind, j in reversed(stack) if kind == "SELECT"), None)
            if sel is None:
                st.problems[i] = (errors.SELECT_UNMATCH, "CASE outside SELECT")
                continue
            st.select_cases[sel].append(i)
        elif isinstance(s, ast.EndSelect):
            if not stack or stack[-1][0] != "SELECT":
                st.problems[i] = (errors.SELECT_UNMATCH, "END SELECT without SELECT")
                continue
            st.select_end[stack.pop()[1]] = i
        elif isinstance(s, ast.Break) or (
            isinstance(s, ast.If)
            and (isinstance(s.then, ast.Break) or isinstance(s.else_, ast.Break))
        ):
            inner = next(
                ((kind, j) for kind, j in reversed(stack) if kind in ("FOR", "WHILE", "SELECT")),
                None,
            )
            if inner is None:
                st.problems[i] = (errors.SELECT_UNMATCH, "BREAK outside SELECT/FOR/WHILE")
            else:
                st.breaks[i] = inner
    unclosed = {
        "FOR": (errors.FOR_NEXT_UNMATCH, "FOR without NEXT"),
        "WHILE": (errors.WHILE_WEND_UNMATCH, "WHILE without WEND"),
        "IF": (errors.IF_ENDIF_UNMATCH, "IF without ENDIF"),
        "SELECT": (errors.SELECT_UNMATCH, "SELECT without END SELECT"),
    }
    for kind, j in stack:
        st.problems[j] = unclosed[kind]
    return st
