"""The small pick-and-place program the grading tests run: it picks at P2 in a GOSUB
routine that lifts 50 mm (line 10), with an output copied from an input on line 6."""

from __future__ import annotations

PROGRAM = """SERVO ON
MOV P1
HOPEN 1
MVS P2
HCLOSE 1
M_OUT(10) = M_IN(8)
GOSUB *UP
END
*UP
MVS P2, -50
RETURN
"""
POINTS = """DEF POS P1=(400,0,450,180,0,180)(7,0)
DEF POS P2=(400,100,400,180,0,180)(7,0)
"""
