"""The layering in docs/ARCHITECTURE.md, checked on the source: a part may import only the
parts below it, and the pure parts (lang, kin, protocol) import nothing that does I/O."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "melfa"

# What each part may import from melfa (besides itself). Mirrors docs/ARCHITECTURE.md.
ALLOWED: dict[str, set[str]] = {
    "lang": set(),
    "kin": {"lang"},  # kin.reach builds lang diagnostics (pure) for points files
    "protocol": set(),
    "vocab": set(),  # the student's words for commands, refusals, activities (pure)
    "live": {"vocab", "protocol"},  # the /api/ws messages and their schema (pure)
    "link": {"protocol"},
    "robot": {"link", "protocol", "lang", "sim"},  # `sim` only for --robot sim, lazily
    "sim": {"protocol", "link", "lang", "kin"},
    "service": {"robot", "link", "protocol", "sim", "kin", "lang", "vocab"},
    "store": {"lang", "vocab"},  # vocab: the kinds of grading; the audit sink is in web
    # Grading on the simulator: pure but for `grade.folder` (reads an assignment folder).
    "grade": {"sim", "lang", "kin", "protocol"},
    "ros": {"service", "robot", "link", "protocol", "sim", "kin", "lang", "vocab"},
    "web": {
        "service",
        "store",
        "ros",
        "robot",
        "link",
        "protocol",
        "sim",
        "kin",
        "lang",
        "vocab",
        "live",
        "grade",
    },
    # A client of the web API; only the pure parts below (file reading, student texts).
    "desktop": {"lang", "protocol", "vocab", "live"},
}

# Standard-library and third-party modules that mean I/O, a clock or a thread.
IMPURE = {
    "socket", "serial", "sqlite3", "asyncio", "threading", "subprocess", "select",
    "os", "pathlib", "io", "time", "urllib", "http", "uvicorn", "fastapi", "pty",
}  # fmt: skip
PURE_PARTS = ("lang", "kin", "protocol", "vocab", "live", "grade")
IO_MODULES = {"grade/folder.py"}  # the one module of a pure part that reads files


def _imports(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.append(node.module)
    return names


def _files(part: str) -> list[Path]:
    base = SRC / part
    return sorted(base.rglob("*.py")) if base.is_dir() else [base.with_suffix(".py")]


@pytest.mark.parametrize("part", sorted(ALLOWED))
def test_a_part_imports_only_the_parts_below_it(part: str) -> None:
    wrong = []
    for path in _files(part):
        for name in _imports(path):
            top = name.split(".")
            other = top[1] if top[0] == "melfa" and len(top) > 1 else None
            if other not in (None, part, "__init__") and other not in ALLOWED[part]:
                wrong.append(f"{path.relative_to(SRC)} imports {name}")
    assert not wrong, "\n".join(wrong)


@pytest.mark.parametrize("part", PURE_PARTS)
def test_pure_parts_do_no_io(part: str) -> None:
    wrong = [
        f"{path.relative_to(SRC)} imports {name}"
        for path in _files(part)
        if path.relative_to(SRC).as_posix() not in IO_MODULES
        for name in _imports(path)
        if name.split(".")[0] in IMPURE
    ]
    assert not wrong, "\n".join(wrong)
