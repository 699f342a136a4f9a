"""Checker case files: expected diagnostics are written as comments inside each .mb4."""

from __future__ import annotations

from pathlib import Path

import pytest

from melfa.lang import check

CASES = sorted((Path(__file__).parent / "cases").glob("*.mb4"))


def expectations(text: str) -> tuple[list[str], set[tuple[int, str]]]:
    points: list[str] = []
    expected: set[tuple[int, str]] = set()
    pending: list[str] = []
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if stripped.lower().startswith("'points:"):
            points = [p.strip() for p in stripped.split(":", 1)[1].split(",") if p.strip()]
        elif stripped.startswith("'!"):
            pending.extend(stripped[2:].split())
        else:
            expected.update((number, rule) for rule in pending)
            pending = []
    return points, expected


@pytest.mark.parametrize("path", CASES, ids=[p.name for p in CASES])
def test_case_file(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    points, expected = expectations(text)
    found = {(d.line, d.rule) for d in check(text, points)}
    assert found == expected


def test_there_are_cases() -> None:
    assert len(CASES) >= 5
