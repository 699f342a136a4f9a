"""Every rule the checker, the points reader, the numbering and the reach check can emit is
documented in docs/diagnostics.md, and nothing else is."""

from __future__ import annotations

import re
from pathlib import Path

import melfa.lang

ROOT = Path(__file__).resolve().parents[2]
LANG = Path(melfa.lang.__file__).parent
NOT_RULES = {"encoding.py"}  # its dashed literals are encodings (utf-8-sig)
SOURCES = [
    *(path for path in sorted(LANG.glob("*.py")) if path.name not in NOT_RULES),
    LANG.parent / "kin" / "reach.py",
]
CLI_RULES = {"file-binary"}  # src/melfa/cli/lang_commands.py (its other literals are encodings)
RULE_LITERAL = re.compile(r'"([a-z]+(?:-[a-z0-9]+)+)"')


def emitted_rules() -> set[str]:
    found = {m for path in SOURCES for m in RULE_LITERAL.findall(path.read_text(encoding="utf-8"))}
    return found | CLI_RULES


def documented_rules() -> set[str]:
    doc = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    return set(re.findall(r"^\| `([a-z0-9-]+)` \|", doc, flags=re.MULTILINE))


def test_every_rule_is_documented() -> None:
    rules = emitted_rules()
    assert len(rules) > 45  # the scan found the rules
    assert rules - documented_rules() == set()
    assert documented_rules() - rules == set()  # no stale entries either


def test_cli_rules_are_really_emitted() -> None:
    cli = (LANG.parent / "cli" / "lang_commands.py").read_text(encoding="utf-8")
    assert all(f'"{rule}"' in cli for rule in CLI_RULES)


def test_rules_seen_in_case_files_are_documented() -> None:
    from melfa.lang import check

    documented = documented_rules()
    for path in (Path(__file__).parent / "cases").glob("*.mb4"):
        for d in check(path.read_text(encoding="utf-8")):
            assert d.rule in documented
