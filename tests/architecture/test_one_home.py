"""One home for the controller's facts: each is declared once, in `melfa.protocol` (or, for a
program's position elements, `melfa.lang.ast`), and every other part reads it there.

Each test below fails when a second copy appears, and names the file and line to change:
hand numbers 1–8 and the override 1–100 (`protocol.limits`), axis names (`protocol.answers`),
the jog modes and error levels (`protocol.jog`, `protocol.error_table`), error numbers and
their ``L2000`` text form (`protocol.error_table`). The browser gets them from the generated
``/model/controller.js`` (tests/web/test_model.py)."""

from __future__ import annotations

import ast
import functools
import io
import re
import tokenize
from collections.abc import Iterator
from pathlib import Path

import pytest

from melfa import protocol
from melfa.lang.ast import JOINT_ELEMENTS, POSITION_ELEMENTS
from melfa.protocol import error_table, span_text

SRC = Path(__file__).resolve().parents[2] / "src" / "melfa"
STATIC = SRC / "web" / "static"


def _python() -> Iterator[Path]:
    yield from sorted(SRC.rglob("*.py"))


def _browser() -> Iterator[Path]:
    yield from sorted((STATIC / "js").glob("*.js"))
    yield from sorted(STATIC.glob("*.html"))


def _where(path: Path, line: int) -> str:
    return f"{path.relative_to(SRC)}:{line}"


@functools.cache
def _lines(path: Path) -> list[str]:
    """The file's lines; for Python, code only: docstrings and comments blanked (prose may
    say "1–8"; code and the texts it shows may not)."""
    text = path.read_text(encoding="utf-8")
    lines = text.splitlines()
    if path.suffix != ".py":
        return lines
    for node in ast.walk(ast.parse(text)):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr):
            doc = body[0]
            if isinstance(doc.value, ast.Constant) and isinstance(doc.value.value, str):
                for number in range(doc.lineno, (doc.end_lineno or doc.lineno) + 1):
                    lines[number - 1] = ""
    for token in tokenize.generate_tokens(io.StringIO(text).readline):
        if token.type == tokenize.COMMENT:
            row, column = token.start
            lines[row - 1] = lines[row - 1][:column]
    return lines


def _matches(paths: Iterator[Path], patterns: list[str], home: set[str]) -> list[str]:
    found = []
    for path in paths:
        if str(path.relative_to(SRC)) in home:
            continue
        for number, text in enumerate(_lines(path), 1):
            if any(re.search(p, text) for p in patterns):
                found.append(f"{_where(path, number)}: {text.strip()}")
    return found


def test_enums_of_controller_facts_are_declared_once_in_protocol() -> None:
    homes: dict[str, list[str]] = {"ErrorLevel": [], "JogMode": [], "JogInch": []}
    for path in _python():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef) and node.name in homes:
                homes[node.name].append(_where(path, node.lineno))
    wrong = {name: places for name, places in homes.items() if len(places) != 1}
    assert not wrong, f"declared more than once (or not at all): {wrong}"
    assert all(places[0].startswith("protocol/") for places in homes.values()), homes


def _error_numbers() -> set[int]:
    named = {v for n, v in vars(error_table).items() if n.isupper() and type(v) is int}
    return {n for n in named | set(error_table.ERROR_MESSAGES) if n >= 1000}


def _target_name(node: ast.Assign | ast.AnnAssign) -> str:
    target = node.targets[0] if isinstance(node, ast.Assign) else node.target
    if isinstance(target, ast.Name):
        return target.id
    return target.attr if isinstance(target, ast.Attribute) else ""


def test_error_numbers_are_named_only_in_the_error_table() -> None:
    """``SERVO_OFF = 2000`` anywhere but `protocol.error_table` is a second copy: import the
    name instead (`from melfa.protocol.error_table import SERVO_OFF`)."""
    numbers = _error_numbers()
    assert {2000, 2160, 2600, 3700, 4220} <= numbers  # the check has something to hold
    copies = []
    for path in _python():
        if path == SRC / "protocol" / "error_table.py":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Assign | ast.AnnAssign):
                continue
            value, name = node.value, _target_name(node)
            is_number = isinstance(value, ast.Constant) and type(value.value) is int
            if is_number and value.value in numbers and re.search("err|number", name, re.I):
                copies.append(f"{_where(path, node.lineno)} {name} = {value.value}")
    assert not copies, "error numbers re-declared:\n" + "\n".join(copies)


def test_the_l2000_form_is_made_only_by_error_code() -> None:
    """A level letter before four digits (``f"{level}{number:04d}"``) is
    `protocol.error_table.error_code`'s job."""
    found = _matches(_python(), [r"\}\{[^{}]*:04d\}"], {"protocol/error_table.py"})
    found += _matches(_browser(), [r"padStart\(4"], set())
    assert not found, "the L2000 form made again:\n" + "\n".join(found)


def _bound_patterns(top: int) -> list[str]:
    """How code writes a range 1..`top` again: comparisons, ``range``, pydantic/typer/Qt
    bounds, a list of that length, and the range in words."""
    return [
        rf"\b[01]\s*<=?\s*[^<>=\n]+<=\s*{top}\b",
        rf"range\(1,\s*{top + 1}\)",
        rf"\ble={top}\b",
        rf"\bmax={top}\b",
        rf"setRange\(1,\s*{top}\)",
        rf"\(None,\)\s*\*\s*{top}\b",
        rf"\b1[.–-]+{top}\b",
    ]


@pytest.mark.parametrize(
    ("fact", "numbers"),
    [("HANDS", protocol.HANDS), ("OVERRIDE_PERCENT", protocol.OVERRIDE_PERCENT)],
)
def test_a_controller_range_has_one_home(fact: str, numbers: range) -> None:
    """Hand numbers and the override are `melfa.protocol.HANDS` and `OVERRIDE_PERCENT`
    (``n in HANDS``, ``span_text(HANDS)``; a program's override: `is_program_override`);
    the browser reads them from /model/controller.js."""
    top = numbers[-1]
    found = _matches(_python(), _bound_patterns(top), {"protocol/limits.py"})
    found += _matches(_browser(), [rf'max="{top}"', rf"<=\s*{top}\b"], set())
    where = "\n".join(found)
    assert not found, f"{span_text(numbers)} written again (read melfa.protocol.{fact}):\n{where}"


def _name_runs(path: Path) -> Iterator[int]:
    """Lines where a tuple or list of strings spells axis names (``("J1", "J2", …)``,
    ``["X", "Y", "Z"]``), or a string ``"XYZABC"`` stands for them."""
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Tuple | ast.List):
            words = [e.value for e in node.elts if isinstance(e, ast.Constant)]
            text = ",".join(w for w in words if isinstance(w, str))
            if "J1,J2" in text or "X,Y,Z" in text:
                yield node.lineno
        elif isinstance(node, ast.Constant) and node.value in ("XYZABC", "XYZ"):
            yield node.lineno


def test_axis_names_have_one_home() -> None:
    """The controller's axis names are `melfa.protocol.JOINT_NAMES` and `POSE_NAMES`; a
    program's position elements (with L1, L2, FL1, FL2, J7, J8) are `melfa.lang.ast`'s. The
    browser imports them from /model/controller.js."""
    found = [
        _where(path, line)
        for path in _python()
        if path != SRC / "protocol" / "answers.py"
        for line in _name_runs(path)
    ]
    found += _matches(
        _browser(), [r"""["']J1["']\s*,\s*["']J2["']""", r"""["']X["']\s*,\s*["']Y["']"""], set()
    )
    assert not found, "axis names written again:\n" + "\n".join(found)


def test_the_languages_elements_begin_with_the_controllers_axes() -> None:
    """lang sits below protocol and cannot import it: the two lists are held together here."""
    assert POSITION_ELEMENTS[:6] == protocol.POSE_NAMES
    assert JOINT_ELEMENTS[:6] == protocol.JOINT_NAMES


@pytest.mark.parametrize("number", [2000, 2160, 1630, 9050, 9250, 9999, 42])
def test_error_code_is_the_level_letter_and_four_digits(number: int) -> None:
    level = protocol.error_level(number)
    code = protocol.error_code(number)
    assert code == (level.letter if level else "") + f"{number:04d}"
