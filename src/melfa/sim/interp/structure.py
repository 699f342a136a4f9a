"""Block matching, done once at load: which NEXT closes which FOR, where an IF's ELSE and
ENDIF are, which CASEs belong to a SELECT, what a BREAK leaves.

The pairing itself is the language's (`melfa.lang.blocks.match_statements`, the one matcher
the checker uses too); this module only turns its result into the step-indexed tables the
flow statements jump by. A structure error is recorded against the step
(`Structure.problems`), not raised: like the controller, a program with a NEXT without FOR
runs until it reaches that line.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from melfa.lang import ast
from melfa.lang.blocks import match_statements

# Nesting depths are checked as the program runs (the loops actually open), not at load.
_RUN_TIME_RULES = frozenset({"loop-nesting", "if-nesting"})


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
    blocks = match_statements(stmts)
    st = Structure()
    for nxt, fors in blocks.next_for.items():
        for k, opener in enumerate(fors):
            st.for_next[opener] = (nxt, k)
    st.while_wend = dict(blocks.while_wend)
    st.wend_while = dict(blocks.wend_while)
    st.if_end = dict(blocks.if_endif)
    st.if_else = {opener: blocks.if_else.get(opener) for opener in blocks.if_endif}
    st.else_end = dict(blocks.else_endif)
    st.select_end = dict(blocks.select_end)
    st.select_cases = {sel: list(cases) for sel, cases in blocks.select_cases.items()}
    st.breaks = {b: (kind.value, opener) for b, (kind, opener) in blocks.break_block.items()}
    for problem in blocks.problems:
        if problem.rule not in _RUN_TIME_RULES:
            st.problems.setdefault(problem.line, (int(problem.code[1:]), problem.message))
    return st
