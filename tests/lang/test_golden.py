"""The checker's findings on a fixed corpus stay exactly as recorded.

A guard for work that must not change behaviour (speed-ups of the lexer, parser and checker):
every diagnostic, with its position, message, rule, code and suggestion, on the example
programs, the checker's case files, the welcome project, every example of
docs/diagnostics.md, the benchmark's generated programs and 600 seeded random programs made
of the language's pieces and of mutated real lines.

When a change is *meant* to change findings, regenerate the record and review its diff:

    .venv/bin/python -m tests.lang.test_golden
"""

from __future__ import annotations

import json
import random
import sys
from pathlib import Path
from typing import Any

from melfa.lang import check
from tests.lang.test_docs import GENERATED, documented_examples
from tests.lang.test_properties import PIECES

ROOT = Path(__file__).resolve().parents[2]
RECORD = Path(__file__).parent / "golden" / "diagnostics.json"
POINTS = ("P1", "P2", "PHOME")


def corpus() -> dict[str, str]:
    """Name -> program text, always the same."""
    sys.path.insert(0, str(ROOT / "bench"))
    try:
        from bench_check import make_program
    finally:
        sys.path.remove(str(ROOT / "bench"))
    files = [
        *sorted((ROOT / "examples").glob("*.MB4")),
        *sorted((ROOT / "tests" / "lang" / "cases").glob("*.mb4")),
        ROOT / "src" / "melfa" / "web" / "static" / "welcome" / "welcome.MB4",
    ]
    out = {str(p.relative_to(ROOT)): p.read_text(encoding="utf-8") for p in files}
    for rule, example in sorted(documented_examples().items()):
        out[f"docs:{rule}"] = GENERATED.get(rule) or example.strip("`").replace("\\n", "\n")
    out["bench:100"] = make_program(100)
    out["bench:1000"] = make_program(1000)
    rng = random.Random(14)
    pieces: tuple[str, ...] = tuple(PIECES.elements)  # type: ignore[attr-defined]
    # Lines of the checker's own case files only: an example program or a docs example added
    # elsewhere must not reshuffle every random program.
    cases = sorted(name for name in out if name.startswith("tests/lang/cases/"))
    real_lines = [line for name in cases for line in out[name].splitlines()]
    for i in range(600):
        if i % 3 == 0:
            text = "".join(rng.choice(pieces) for _ in range(rng.randint(1, 60)))
        else:
            text = "\n".join(rng.choice(real_lines) for _ in range(rng.randint(1, 12))) + "\n"
            for _ in range(rng.randint(0, 4)):
                at = rng.randrange(len(text) + 1)
                how = rng.randrange(3)
                if how == 0:
                    text = text[:at] + text[at + 1 :]
                elif how == 1:
                    text = text[:at] + rng.choice(pieces) + text[at:]
                else:
                    text = text[:at] + chr(rng.randrange(32, 127)) + text[at:]
        out[f"random:{i}"] = text
    return out


def findings(text: str) -> list[list[Any]]:
    fields = ("line", "column", "end_line", "end_column", "message", "rule", "code", "suggestion")
    return [[d.severity.value, *(getattr(d, f) for f in fields)] for d in check(text, POINTS)]


def record() -> dict[str, list[list[Any]]]:
    return {name: findings(text) for name, text in corpus().items()}


def test_findings_are_as_recorded() -> None:
    recorded = json.loads(RECORD.read_text(encoding="utf-8"))
    now = json.loads(json.dumps(record()))  # tuples and lists compare alike
    assert now.keys() == recorded.keys()
    changed = [name for name in now if now[name] != recorded[name]]
    assert not changed, f"findings changed for {len(changed)} programs, e.g. {changed[:5]}"


if __name__ == "__main__":
    RECORD.parent.mkdir(exist_ok=True)
    found = record()
    lines = (f"{json.dumps(k)}: {json.dumps(v, ensure_ascii=False)}" for k, v in found.items())
    RECORD.write_text("{\n" + ",\n".join(lines) + "\n}\n", "utf-8")  # a line per program
    print(f"wrote {RECORD}")
