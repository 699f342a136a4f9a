"""The browser tests share one server a session: an account one test adds, another must
not add again (`melfa users add` refuses a name taken, so the second test fails, but only
when both run in one session, as in CI, never alone). Read from the files, so it holds
whichever files run."""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path


def test_each_account_is_added_once() -> None:
    adders: dict[str, list[str]] = defaultdict(list)
    for path in sorted(Path(__file__).parent.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and node.func.attr == "add_user"
                and node.args
                and isinstance(node.args[0], ast.Constant)
            ):
                adders[str(node.args[0].value)].append(f"{path.name}:{node.lineno}")
    assert len(adders) >= 20  # the files were read
    twice = {name: where for name, where in adders.items() if len(where) > 1}
    assert not twice, f"accounts added twice on the session's one server: {twice}"
