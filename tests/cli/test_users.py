"""`melfa users add|passwd|remove|list|import` against a real database file in tmp_path."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

import melfa.cli.users_commands  # noqa: F401  (registers the commands)
from melfa.cli.typer_app import app
from melfa.store import Store
from tests.store.conftest import CHEAP

runner = CliRunner()


@pytest.fixture(autouse=True)
def cheap_hashes(monkeypatch: pytest.MonkeyPatch) -> None:
    """Real Argon2 with tiny parameters: these tests are about the CLI, not hash cost."""
    monkeypatch.setattr("melfa.store.passwords.PasswordHasher", lambda: CHEAP)


@pytest.fixture
def data(tmp_path: Path) -> Path:
    return tmp_path / "data"


def users(data: Path, *args: str, input: str | None = None) -> tuple[int, str, str]:
    result = runner.invoke(app, ["users", *args, "--data", str(data)], input=input)
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return result.exit_code, result.stdout, result.stderr


def listed(data: Path) -> list[dict[str, object]]:
    code, out, _ = users(data, "list", "--json")
    assert code == 0
    rows: list[dict[str, object]] = json.loads(out)
    return rows


def authenticate(data: Path, username: str, password: str) -> bool:
    with Store.open_dir(data, create=False) as store:
        return store.accounts.authenticate(username, password) is not None


def test_add_with_password_on_stdin_then_list(data: Path) -> None:
    code, out, err = users(
        data,
        "add",
        "Ada",
        "--role",
        "instructor",
        "--group",
        "G1",
        "--name",
        "Ada L",
        "--password-stdin",
        input="correct horse\n",
    )
    assert code == 0, err
    assert "created ada (instructor, group G1)" in err
    assert out == ""
    assert (data / "melfa.sqlite3").is_file()
    assert authenticate(data, "ada", "correct horse")
    [row] = listed(data)
    assert (row["username"], row["name"], row["role"], row["group"]) == (
        "ada",
        "Ada L",
        "instructor",
        "G1",
    )
    assert not any("hash" in key or "password" in key for key in row)


def test_add_without_a_terminal_generates_and_prints_once(data: Path) -> None:
    code, out, err = users(data, "add", "bob")
    assert code == 0, err
    password = out.strip()
    assert len(password) >= 12
    assert "shown only now" in err
    assert authenticate(data, "bob", password)


def test_list_as_a_table_has_no_hashes(data: Path) -> None:
    users(data, "add", "ada", "--group", "G1", "--password-stdin", input="kettle-moon-1\n")
    code, out, err = users(data, "list")
    assert code == 0
    assert "ada" in out and "G1" in out and "student" in out and "never" in out
    assert "argon2" not in out
    assert "1 account" in err


def test_add_mistakes_are_clear_and_not_tracebacks(data: Path) -> None:
    users(data, "add", "ada", "--password-stdin", input="kettle-moon-1\n")
    code, _, err = users(data, "add", "ada", "--password-stdin", input="kettle-moon-2\n")
    assert code == 1
    assert "already exists" in err
    code, _, err = users(data, "add", "bad name", "--generate")
    assert code == 2
    assert "not a valid username" in err
    code, _, err = users(data, "add", "cy", "--password-stdin", input="short\n")
    assert code == 2
    assert "at least 8" in err
    code, _, err = users(data, "add", "cy", "--role", "wizard")
    assert code == 2
    code, _, err = users(data, "add", "cy", "--password-stdin", "--generate")
    assert code == 2
    assert [r["username"] for r in listed(data)] == ["ada"]


def test_passwd(data: Path) -> None:
    users(data, "add", "ada", "--password-stdin", input="kettle-moon-1\n")
    code, _, err = users(data, "passwd", "ada", "--password-stdin", input="kettle-moon-2\n")
    assert code == 0, err
    assert authenticate(data, "ada", "kettle-moon-2")
    assert not authenticate(data, "ada", "kettle-moon-1")
    code, out, _ = users(data, "passwd", "ada", "--generate")
    assert code == 0
    assert authenticate(data, "ada", out.strip())
    code, _, err = users(data, "passwd", "nobody", "--generate")
    assert code == 1
    assert "no user 'nobody'" in err


def test_remove_asks_unless_yes(data: Path) -> None:
    users(data, "add", "ada", "--generate")
    users(data, "add", "bob", "--generate")
    code, _, err = users(data, "remove", "ada", input="n\n")
    assert code == 1
    assert "nothing removed" in err
    code, _, err = users(data, "remove", "ada", input="")  # Ctrl+D at the question
    assert (code, "nothing removed" in err) == (1, True), err
    code, _, _ = users(data, "remove", "ada", input="y\n")
    assert code == 0
    code, _, _ = users(data, "remove", "bob", "--yes")
    assert code == 0
    assert listed(data) == []
    code, _, err = users(data, "remove", "bob", "--yes")
    assert code == 1


def test_last_admin_cannot_be_removed(data: Path) -> None:
    users(data, "add", "root", "--role", "admin", "--generate")
    code, _, err = users(data, "remove", "root", "--yes")
    assert code == 1
    assert "last enabled admin" in err


def test_read_commands_need_an_existing_database(data: Path) -> None:
    code, _, err = users(data, "list")
    assert code == 2
    assert "no database" in err
    assert not data.exists()


def test_data_dir_from_environment(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MELFA_DATA", str(tmp_path / "envdata"))
    result = runner.invoke(app, ["users", "add", "ada", "--generate"])
    assert result.exit_code == 0
    assert (tmp_path / "envdata" / "melfa.sqlite3").is_file()


def test_survives_a_server_restart(data: Path) -> None:
    """A server holding the file open sees the CLI's changes, and so does a fresh open."""
    users(data, "add", "ada", "--password-stdin", input="kettle-moon-1\n")
    with Store.open_dir(data) as server:
        users(data, "passwd", "ada", "--password-stdin", input="kettle-moon-2\n")
        assert server.accounts.authenticate("ada", "kettle-moon-2") is not None
    assert authenticate(data, "ada", "kettle-moon-2")
