"""The desktop client's own layers (`melfa.desktop`'s docstring), checked on the source:
a module imports only the desktop modules of its own layer or below, widgets never reach
into the presenter (the window wires the two), and the layers below Qt import no Qt."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

DESKTOP = Path(__file__).resolve().parents[2] / "src" / "melfa" / "desktop"

LAYERS: dict[str, tuple[int, frozenset[str]]] = {
    # Pure Python, no Qt: file rules, the HTTP client, the live feed, what it says.
    "pure": (0, frozenset({"files", "api", "messages", "live", "words"})),
    # Qt's threads and timers, the look, the dialogs and the View protocol.
    "qt": (1, frozenset({"tasks", "hold", "style", "dialogs", "view"})),
    # What each intent means and what the live feed says: no widget.
    "presenter": (2, frozenset({"live_state", "presenter"})),
    # The panels: they show what they are given and never call the presenter.
    "widgets": (2, frozenset({"position", "robot_box", "program_box", "jogpad", "login"})),
    # The window wires panels to the presenter; app starts it all.
    "top": (3, frozenset({"window", "app"})),
}
"""Layer name -> (height, modules). Presenter and widgets stand side by side at one height:
neither may import the other."""

LAYER_OF = {module: name for name, (_, modules) in LAYERS.items() for module in modules}


def _desktop_imports(path: Path) -> list[tuple[str, str]]:
    """(imported desktop module, its full name) for each import of ``path``."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        names = []
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [node.module]
        for name in names:
            parts = name.split(".")
            if parts[:2] == ["melfa", "desktop"] and len(parts) > 2:
                found.append((parts[2], name))
            elif parts[0] == "PySide6":
                found.append(("PySide6", name))
    return found


MODULES = sorted(p for p in DESKTOP.glob("*.py") if p.stem != "__init__")


def test_every_desktop_module_has_a_layer() -> None:
    assert sorted(p.stem for p in MODULES) == sorted(LAYER_OF)


@pytest.mark.parametrize("path", MODULES, ids=lambda p: p.stem)
def test_a_desktop_module_imports_only_its_layer_and_below(path: Path) -> None:
    mine = LAYER_OF[path.stem]
    height = LAYERS[mine][0]
    wrong = []
    for module, name in _desktop_imports(path):
        if module == "PySide6":
            if mine == "pure":
                wrong.append(f"{path.stem} ({mine}) imports Qt: {name}")
            continue
        theirs = LAYER_OF.get(module)
        if theirs is None:
            continue  # not a module of its own (the package)
        if theirs != mine and LAYERS[theirs][0] >= height:
            wrong.append(f"{path.stem} ({mine}) imports {name} ({theirs})")
    assert not wrong, "\n".join(wrong)
