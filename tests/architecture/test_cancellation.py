"""No ``asyncio.wait_for`` in melfa: in Python 3.11 (the version melfa runs on) it returns
what arrived in the very moment its task is cancelled and drops the cancellation. It did so
four times before this test (a socket's state pump, a co-editing room's saver and reader, a
rosbridge sign-in, a test clock's driver): each ran on after it was told to stop. Wait with
``asyncio.timeout`` or ``asyncio.timeout_at`` instead (`Subscription.get_within`). The
benchmarks in bench/ are held to it too: a figure measured by a wait that ran on after it
was stopped is not the figure of the code it names."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SEARCHED = (ROOT / "src" / "melfa", ROOT / "bench")


def _wait_fors(tree: ast.AST) -> list[int]:
    lines = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr == "wait_for":
            if isinstance(node.value, ast.Name) and node.value.id == "asyncio":
                lines.append(node.lineno)
        elif isinstance(node, ast.ImportFrom) and node.module == "asyncio":
            lines += [node.lineno for alias in node.names if alias.name == "wait_for"]
    return sorted(lines)


def test_nothing_waits_with_asyncio_wait_for() -> None:
    found = [
        f"{path.relative_to(ROOT)}:{line}"
        for folder in SEARCHED
        for path in sorted(folder.rglob("*.py"))
        for line in _wait_fors(ast.parse(path.read_text(encoding="utf-8")))
    ]
    assert found == [], f"asyncio.wait_for swallows a cancellation in Python 3.11: {found}"


def test_the_search_finds_it() -> None:
    written = "import asyncio\nfrom asyncio import wait_for\nawait asyncio.wait_for(f(), 1)\n"
    assert _wait_fors(ast.parse(written)) == [2, 3]
