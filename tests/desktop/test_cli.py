"""`melfa desktop` as a command: Qt stays out of `import melfa.cli`, and a machine
without the extra gets one line telling how to install it, not a traceback."""

from __future__ import annotations

import os
import subprocess
import sys

BLOCK_QT = "import sys; sys.modules['PySide6'] = None\n"  # as if the extra were not installed


def run_python(code: str) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k != "QT_QPA_PLATFORM"}
    return subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60, env=env
    )


def test_importing_the_cli_does_not_import_qt() -> None:
    result = run_python(
        "import sys, melfa.cli, melfa.desktop.api, melfa.desktop.live\n"
        "print(sorted(m for m in sys.modules if m.startswith('PySide6')))"
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "[]"


def test_without_pyside6_the_command_says_how_to_install() -> None:
    result = run_python(
        BLOCK_QT + "from melfa.cli import main\nsys.argv = ['melfa', 'desktop']\nmain()"
    )
    assert result.returncode == 2
    assert "needs PySide6" in result.stderr
    assert "pip install 'melfa[desktop]'" in result.stderr
    assert "Traceback" not in result.stderr


def test_a_bad_server_address_is_a_usage_error() -> None:
    result = run_python(
        "import sys\nfrom melfa.cli import main\n"
        "sys.argv = ['melfa', 'desktop', '--server', 'ftp://lab']\nmain()"
    )
    assert result.returncode == 2
    assert "not a server address" in result.stderr
    assert "Traceback" not in result.stderr


def test_without_a_display_the_command_says_so() -> None:
    code = (
        "import os, sys\nfor v in ('DISPLAY', 'WAYLAND_DISPLAY', 'QT_QPA_PLATFORM'):\n"
        "    os.environ.pop(v, None)\n"
        "from melfa.cli import main\nsys.argv = ['melfa', 'desktop']\nmain()"
    )
    result = run_python(code)
    assert result.returncode == 2
    assert "there is no display here" in result.stderr
    assert "Traceback" not in result.stderr


def test_help_names_the_options() -> None:
    result = run_python(
        "import sys\nfrom melfa.cli import main\nsys.argv = ['melfa', 'desktop', '--help']\nmain()"
    )
    assert result.returncode == 0, result.stderr
    assert "--server" in result.stdout and "--user" in result.stdout
