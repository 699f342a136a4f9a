"""`melfa users import`: yearly enrolment, all rows or none."""

from __future__ import annotations

import csv
import stat
from pathlib import Path

import pytest
from typer.testing import CliRunner

import melfa.cli.users_commands  # noqa: F401  (registers the commands)
from melfa.cli.typer_app import app
from melfa.store import Role, Store
from tests.store.conftest import CHEAP

runner = CliRunner()


@pytest.fixture(autouse=True)
def cheap_hashes(monkeypatch: pytest.MonkeyPatch) -> None:
    """Real Argon2 with tiny parameters: these tests are about the CLI, not hash cost."""
    monkeypatch.setattr("melfa.store.passwords.PasswordHasher", lambda: CHEAP)


GOOD = """username,name,group,role,password
ana,Ana Pérez,G1,,
ben,Ben Ruiz,G1,student,
cai,Cai Li,G2,,given-password
tom,Tom Instructor,,instructor,teacher-pass
"""

BAD = """username,name,group,role,password
ana,Ana Pérez,G1,,
b d,Bad Name,G1,,
cai,Cai Li,G2,wizard,
ana,Ana Again,G3,,
dee,Dee,G1,student,short
eve,Eve,G1
fay,Fay,G1,,
"""


@pytest.fixture
def data(tmp_path: Path) -> Path:
    return tmp_path / "data"


def run(data: Path, *args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, ["users", "import", *args, "--data", str(data)])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return result.exit_code, result.stdout, result.stderr


def test_import_creates_accounts_and_writes_generated_passwords(tmp_path: Path, data: Path) -> None:
    students = tmp_path / "students.csv"
    students.write_text(GOOD, encoding="utf-8")
    out = tmp_path / "passwords.csv"
    code, _, err = run(data, str(students), "--out", str(out))
    assert code == 0, err
    assert "created 4, updated 0, skipped 0" in err
    assert stat.S_IMODE(out.stat().st_mode) == 0o600
    with out.open(newline="", encoding="utf-8") as f:
        handed_out = list(csv.DictReader(f))
    assert [r["username"] for r in handed_out] == ["ana", "ben"]
    assert handed_out[0]["name"] == "Ana Pérez"
    with Store.open_dir(data, create=False) as store:
        for row in handed_out:
            assert store.accounts.authenticate(row["username"], row["password"]) is not None
        assert store.accounts.authenticate("cai", "given-password") is not None
        tom = store.accounts.get_user("tom")
        assert (tom.role, tom.group) == (Role.INSTRUCTOR, None)
        assert [u.username for u in store.accounts.list_users(group="G1")] == ["ana", "ben"]


def test_bad_rows_import_nothing_and_are_listed_by_line(tmp_path: Path, data: Path) -> None:
    students = tmp_path / "students.csv"
    students.write_text(BAD, encoding="utf-8")
    out = tmp_path / "passwords.csv"
    code, _, err = run(data, str(students), "--out", str(out))
    assert code == 1
    lines = {
        int(line.split(":")[1]): line for line in err.splitlines() if line.startswith(str(students))
    }
    assert sorted(lines) == [3, 4, 5, 6, 7]
    assert "not a valid username" in lines[3]
    assert "not a role" in lines[4]
    assert "already on line 2" in lines[5]
    assert "at least 8" in lines[6]
    assert "3 fields, expected 5" in lines[7]
    assert "nothing was imported" in err
    assert not out.exists()
    assert not data.exists()  # checked before the database was even opened


def test_bad_header_is_reported_on_line_1(tmp_path: Path, data: Path) -> None:
    students = tmp_path / "s.csv"
    students.write_text("user,name,team\nana,Ana,G1\n")
    code, _, err = run(data, str(students))
    assert code == 1
    assert f"{students}:1: missing column(s) username, group; unknown column(s) user, team" in err


def test_generated_passwords_need_an_out_file(tmp_path: Path, data: Path) -> None:
    students = tmp_path / "s.csv"
    students.write_text("username,name,group\nana,Ana,G1\n")
    code, _, err = run(data, str(students))
    assert code == 2
    assert "--out" in err
    with Store.open_dir(data) as store:
        assert store.accounts.list_users() == []


def test_existing_out_file_is_never_overwritten(tmp_path: Path, data: Path) -> None:
    students = tmp_path / "s.csv"
    students.write_text("username,name,group\nana,Ana,G1\n")
    out = tmp_path / "passwords.csv"
    out.write_text("last year's passwords\n")
    code, _, err = run(data, str(students), "--out", str(out))
    assert code == 2
    assert "already exists" in err
    assert out.read_text() == "last year's passwords\n"


def test_existing_users_are_skipped_or_updated(tmp_path: Path, data: Path) -> None:
    first = tmp_path / "first.csv"
    first.write_text("username,name,group,password\nana,Ana,G1,lantern-oak-1\n")
    assert run(data, str(first))[0] == 0
    second = tmp_path / "second.csv"
    second.write_text("username,name,group,password\nana,Ana María,G2,\nbea,Bea,G2,lantern-oak-2\n")
    code, _, err = run(data, str(second))
    assert code == 0, err
    assert "created 1, updated 0, skipped 1 (already exist: ana)" in err
    with Store.open_dir(data) as store:
        assert store.accounts.get_user("ana").group == "G1"
    code, _, err = run(data, str(second), "--update")
    assert code == 0, err
    assert "created 0, updated 2" in err
    with Store.open_dir(data) as store:
        ana = store.accounts.get_user("ana")
        assert (ana.display_name, ana.group) == ("Ana María", "G2")
        # No password in the file: the old one still works.
        assert store.accounts.authenticate("ana", "lantern-oak-1") is not None


def test_missing_file_is_a_usage_error(tmp_path: Path, data: Path) -> None:
    code, _, err = run(data, str(tmp_path / "nope.csv"))
    assert code == 2
    assert "cannot read" in err


def test_a_refusal_halfway_rolls_back_every_row(tmp_path: Path, data: Path) -> None:
    with Store.open_dir(data) as store:
        store.accounts.create_user("root", "kettle-moon-1", role=Role.ADMIN)
    students = tmp_path / "s.csv"
    students.write_text("username,name,group,role\nana,Ana,G1,\nroot,Root,,student\n")
    out = tmp_path / "passwords.csv"
    code, _, err = run(data, str(students), "--out", str(out), "--update")
    assert code == 1
    assert "line 3: cannot make 'root' a student: it is the last enabled admin" in err
    assert not out.exists()
    with Store.open_dir(data) as store:
        assert [u.username for u in store.accounts.list_users()] == ["root"]
        assert store.accounts.find_group("G1") is None
