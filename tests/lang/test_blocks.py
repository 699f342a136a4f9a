"""Block structure tables: what an interpreter needs to jump."""

from __future__ import annotations

from melfa.lang import match_blocks, parse

PROGRAM = """FOR A = 1 TO 2
  FOR B = 1 TO 2
    WHILE M1 < 3
      M1 = M1 + 1
    WEND
  NEXT B, A
IF M1 THEN
  HOPEN 1
ELSE
  HCLOSE 1
ENDIF
SELECT M2
CASE 1
  BREAK
CASE IS > 3
  IF M3 THEN
    BREAK
  ENDIF
DEFAULT
END SELECT
"""


def test_tables() -> None:
    blocks = match_blocks(parse(PROGRAM))
    assert blocks.problems == []
    assert blocks.for_next == {0: 5, 1: 5}
    assert blocks.next_for == {5: (1, 0)}
    assert blocks.while_wend == {2: 4}
    assert blocks.wend_while == {4: 2}
    assert blocks.if_else == {6: 8}
    assert blocks.if_endif == {6: 10, 15: 17}
    assert blocks.else_endif == {8: 10}
    assert blocks.select_cases == {11: (12, 14, 18)}
    assert blocks.select_end == {11: 19}
    assert blocks.break_target == {13: 19, 16: 19}


def test_single_line_if_is_not_a_block() -> None:
    blocks = match_blocks(parse("IF M1 THEN HOPEN 1 ELSE HCLOSE 1\n"))
    assert blocks.if_endif == {} and blocks.problems == []


def test_unclosed_blocks_are_reported_once_each() -> None:
    blocks = match_blocks(parse("FOR A = 1 TO 2\nWHILE 1\nIF M1 THEN\nNEXT A\n"))
    assert [(p.line, p.rule) for p in blocks.problems] == [
        (1, "while-without-wend"),
        (2, "if-without-endif"),
    ]
    assert blocks.for_next == {0: 3}
