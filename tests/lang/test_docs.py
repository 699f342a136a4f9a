"""Every rule the checker can emit is documented in docs/diagnostics.md."""

from __future__ import annotations

import re
from pathlib import Path

import melfa.lang

ROOT = Path(__file__).resolve().parents[2]
SOURCES = [
    Path(melfa.lang.__file__).parent / name for name in ("parser.py", "check.py", "blocks.py")
]
RULE_LITERAL = re.compile(r'"([a-z]+(?:-[a-z0-9]+)+)"')


def emitted_rules() -> set[str]:
    return {m for path in SOURCES for m in RULE_LITERAL.findall(path.read_text(encoding="utf-8"))}


def test_every_rule_is_documented() -> None:
    doc = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    documented = set(re.findall(r"^\| `([a-z0-9-]+)` \|", doc, flags=re.MULTILINE))
    rules = emitted_rules()
    assert len(rules) > 30  # the scan found the rules
    assert rules - documented == set()
    assert documented - rules == set()  # no stale entries either


def test_rules_seen_in_case_files_are_documented() -> None:
    from melfa.lang import check

    doc = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    for path in (Path(__file__).parent / "cases").glob("*.mb4"):
        for d in check(path.read_text(encoding="utf-8")):
            assert f"`{d.rule}`" in doc
