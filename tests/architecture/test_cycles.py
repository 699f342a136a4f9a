"""Packages whose modules must form no import cycle, and take no imports inside functions.

Every import counts, also those under ``if TYPE_CHECKING:`` and inside functions: a cycle
hidden that way is still a cycle (the interpreter used to be one, held together by imports
inside functions).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src"

ACYCLIC = ("melfa.sim", "melfa.sim.interp", "melfa.sim.debug")

NO_CYCLE = (
    *ACYCLIC, "melfa.lang", "melfa.kin", "melfa.protocol", "melfa.vocab", "melfa.live",
    "melfa.link", "melfa.robot", "melfa.sim.handlers", "melfa.grade", "melfa.store",
    "melfa.service", "melfa.ros", "melfa.web", "melfa.web.routes", "melfa.desktop", "melfa.cli",
)  # fmt: skip
"""Every package: no cycle among its modules (imports inside functions are allowed outside
`ACYCLIC`, for start-up time, but still count)."""


def _modules(package: str) -> dict[str, Path]:
    base = SRC / package.replace(".", "/")
    return {f"{package}.{p.stem}": p for p in sorted(base.glob("*.py")) if p.stem != "__init__"}


def _edges(package: str, path: Path, known: set[str]) -> set[str]:
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names if a.name in known}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module in known:
                out.add(node.module)
            elif node.module == package:
                out |= {f"{package}.{a.name}" for a in node.names} & known
    return out


def _cycle(graph: dict[str, set[str]]) -> list[str] | None:
    state: dict[str, int] = {}
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                return [*path[path.index(nxt) :], nxt]
            if nxt not in state and (found := visit(nxt)) is not None:
                return found
        path.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state and (found := visit(node)) is not None:
            return found
    return None


@pytest.mark.parametrize("package", NO_CYCLE)
def test_package_has_no_import_cycle(package: str) -> None:
    modules = _modules(package)
    assert modules, f"{package} has no modules"
    graph = {name: _edges(package, path, set(modules)) for name, path in modules.items()}
    assert _cycle(graph) is None, " -> ".join(_cycle(graph) or [])


@pytest.mark.parametrize("package", ACYCLIC)
def test_package_imports_at_the_top_only(package: str) -> None:
    inside = []
    for name, path in _modules(package).items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                for sub in ast.walk(node):
                    if isinstance(sub, ast.Import | ast.ImportFrom):
                        inside.append(f"{name}:{sub.lineno}")
    assert inside == []


def test_the_cycle_finder_finds_a_cycle() -> None:
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _cycle({"a": {"b"}, "b": set()}) is None
