"""`melfa.lang.ast` is the one public home of the tree's node names: each family module's nodes
are re-exported there, and `walk` (built from that module's names) reaches every one."""

from __future__ import annotations

import enum

import pytest

from melfa.lang import ast as A  # noqa: N812
from melfa.lang import ast_commands, ast_defs, ast_expr, ast_flow, ast_io
from melfa.lang.parser import parse
from melfa.lang.record import Record

FAMILIES = (ast_expr, ast_commands, ast_flow, ast_defs, ast_io)


def _defined_in(module: object) -> dict[str, type]:
    return {
        name: obj
        for name, obj in vars(module).items()
        if isinstance(obj, type)
        and issubclass(obj, Record | enum.Enum)
        and obj.__module__ == getattr(module, "__name__", None)
    }


@pytest.mark.parametrize("family", FAMILIES, ids=lambda m: m.__name__)
def test_every_class_of_a_family_is_a_name_of_ast(family: object) -> None:
    classes = _defined_in(family)
    assert classes
    for name, cls in classes.items():
        assert getattr(A, name, None) is cls, name
        assert name in A.__all__, name


def test_walk_knows_every_node_class() -> None:
    nodes = {
        cls
        for module in (*FAMILIES, A)
        for cls in _defined_in(module).values()
        if issubclass(cls, Record) and cls is not A.ParseIssue
    }
    assert nodes - set(A.CHILD_FIELDS) == set()


def test_walk_reaches_into_every_family() -> None:
    program = parse(
        "MOV P1, -50 WTH M_OUT(17) = 1 DLY 0.5\n"
        "IF M1 > 2 THEN HOPEN M2 ELSE *L\n"
        "DEF POS PX = (1, 2, 3, 0, 0, 0)(7, 0)\n"
        "PRINT #1, SIN(M3)\n"
    )
    names = {n.name for line in program.lines for n in A.walk(line) if isinstance(n, A.Name)}
    assert names == {"P1", "M_OUT", "M1", "M2", "PX", "M3"}
