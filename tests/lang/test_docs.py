"""Every rule the checker, the points reader, the numbering and the reach check can emit is
documented in docs/diagnostics.md, and nothing else is."""

from __future__ import annotations

import re
from pathlib import Path

import melfa.lang
from melfa.kin.reach import reach_diagnostics
from melfa.lang import check
from melfa.lang.numbering import renumber
from melfa.lang.project import check_project

ROOT = Path(__file__).resolve().parents[2]
LANG = Path(melfa.lang.__file__).parent
NOT_RULES = {"encoding.py"}  # its dashed literals are encodings (utf-8-sig)
SOURCES = [
    *(path for path in sorted(LANG.glob("*.py")) if path.name not in NOT_RULES),
    LANG.parent / "kin" / "reach.py",
]
CLI_RULES = {"file-binary"}  # src/melfa/cli/checking.py (its other literals are encodings)
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
    cli = (LANG.parent / "cli" / "checking.py").read_text(encoding="utf-8")
    assert all(f'"{rule}"' in cli for rule in CLI_RULES)


def test_rules_seen_in_case_files_are_documented() -> None:
    from melfa.lang import check

    documented = documented_rules()
    for path in (Path(__file__).parent / "cases").glob("*.mb4"):
        for d in check(path.read_text(encoding="utf-8")):
            assert d.rule in documented


# --- every rule has an example in docs/diagnostics.md, and the example gives that rule ----

GENERATED = {  # examples described in words in the doc (too long to write there)
    "loop-nesting": "".join(f"FOR M{i} = 1 TO 2\n" for i in range(17))
    + "".join(f"NEXT M{i}\n" for i in reversed(range(17))),
    "if-nesting": "IF M1 = 1 THEN\n" * 9 + "ENDIF\n" * 9,
    "too-many-targets": "ON M1 GOTO " + ", ".join(["*A"] * 33) + "\n*A\n",
    "line-too-long": "M1 = " + " + ".join(["1"] * 62) + "\n",
    "def-too-long": "DEF POS " + ", ".join(f"PX{i:03d}" for i in range(21)) + "\n",
}
NOT_FROM_TEXT = {"internal-error", "file-binary", "numbering-overflow"}  # tested elsewhere


def documented_examples() -> dict[str, str]:
    doc = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    section = doc.split("## Examples", 1)[1]
    return dict(re.findall(r"^\| `([a-z0-9-]+)` \| (.+?) \|$", section, flags=re.MULTILINE))


def rules_of(rule: str, example: str) -> set[str]:
    text = example.replace("\\n", "\n") + "\n"
    if rule.startswith("point"):
        return {d.rule for d in check_project([], [text], reach_diagnostics).points[0]}
    if rule.startswith("numbering"):
        return {d.rule for d in renumber(text).diagnostics}
    return {d.rule for d in check(text, ["P1", "P2"])}


def test_every_rule_has_an_example() -> None:
    assert set(documented_examples()) == documented_rules()


def test_every_example_gives_its_rule() -> None:
    for rule, example in documented_examples().items():
        if rule in NOT_FROM_TEXT:
            continue
        code = GENERATED.get(rule)
        if code is None:
            assert example.startswith("`") and example.endswith("`"), rule
            code = example.strip("`")
        assert rule in rules_of(rule, code), (rule, code)
