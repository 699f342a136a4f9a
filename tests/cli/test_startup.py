"""`melfa check` starts fast: it loads only the language toolkit, not the simulator, the
store, the web server or numpy (editors and pre-commit hooks run it on every save)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from melfa.cli.typer_app import COMMAND_MODULES, app

HEAVY = (
    "melfa.sim", "melfa.store", "melfa.kin", "melfa.web", "melfa.robot", "numpy", "fastapi",
    "typer", "rich", "pydantic",
)  # fmt: skip


def _modules_after(argv: list[str]) -> set[str]:
    code = (
        "import sys\nfrom melfa.cli import main\n"
        f"sys.argv = {['melfa', *argv]!r}\n"
        "try:\n    main()\nexcept SystemExit:\n    pass\n"
        "print(' '.join(sys.modules))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    ).stdout
    return set(out.splitlines()[-1].split())


def test_check_imports_nothing_heavy(tmp_path: Path) -> None:
    program = tmp_path / "p.MB4"
    program.write_text("10 MOV P1\n20 END\n", encoding="utf-8")
    loaded = _modules_after(["check", str(program)])
    assert "melfa.lang.check" in loaded  # it did check
    assert not [m for m in loaded if m.startswith(HEAVY)]


def test_check_through_typer_gives_the_same_answer(tmp_path: Path) -> None:
    """The Typer command `check` forwards to the same function (one set of options)."""
    program = tmp_path / "p.MB4"
    program.write_text("10 HOPEN\n", encoding="utf-8")
    result = CliRunner().invoke(app, ["check", str(program), "--format", "json"])
    assert result.exit_code == 1
    assert '"L4220"' in result.stdout


def test_points_files_load_the_robot_model_only_when_there_are_points(tmp_path: Path) -> None:
    points = tmp_path / "p.POS"
    points.write_text("P1=(400,0,600,180,0,180)(7,0)\n", encoding="utf-8")
    assert "melfa.kin.reach" in _modules_after(["check", str(points)])


def test_the_command_table_names_the_module_of_every_command() -> None:
    """melfa.cli.typer_app.COMMAND_MODULES is the lazy loader's map; keep it true."""
    registered = {
        (info.name or info.callback.__name__.replace("_", "-")): info.callback.__module__
        for info in app.registered_commands
        if info.callback is not None
    }
    registered |= {g.name: g.typer_instance.registered_commands[0].callback.__module__
                   for g in app.registered_groups if g.name}  # fmt: skip
    for command, module in COMMAND_MODULES.items():
        assert registered.get(command) == f"melfa.cli.{module}", command
