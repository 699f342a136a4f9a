"""Import and export of .MB4 / .POS files, alone and through a workspace."""

from __future__ import annotations

import pytest

from melfa.store import (
    FileKind,
    SaveReason,
    Store,
    TransferError,
    WrongExtension,
    file_kind,
    points_from_file,
    points_to_file,
    program_from_file,
    program_to_file,
)

NUMBERED = "10 SERVO ON\n20 *LOOP\n30 MOV P1\n40 HOPEN 1\n50 GOTO 20\n60 END\n"
POINTS = "DEF POS P1=(400.00,0.00,300.00,180.00,0.00,180.00)(7,0)\n"


def test_program_import_strips_numbers_and_export_puts_them_back() -> None:
    stripped = program_from_file("pick.MB4", NUMBERED.replace("\n", "\r\n").encode())
    assert stripped == "SERVO ON\n20 *LOOP\nMOV P1\nHOPEN 1\nGOTO 20\nEND\n"
    exported = program_to_file(stripped, "ada")
    assert exported.filename == "ada.MB4"
    assert exported.text == NUMBERED


def test_program_export_of_unnumbered_labels() -> None:
    exported = program_to_file("SERVO ON\n*A\nGOTO *A\n")
    assert exported.text == "10 SERVO ON\n20 *A\n30 GOTO *A\n"


def test_program_that_cannot_be_numbered_is_refused_with_a_location() -> None:
    with pytest.raises(TransferError) as err:
        program_to_file("MOV P1\nGOTO 500\n")
    assert err.value.diagnostics
    assert err.value.diagnostics[0].line == 2


def test_program_import_with_duplicate_numbers_is_refused() -> None:
    with pytest.raises(TransferError) as err:
        program_from_file("x.mb4", "10 MOV P1\n10 END\n")
    assert err.value.diagnostics[0].line == 2


def test_points_round_trip() -> None:
    text = points_from_file("points.pos", POINTS.encode("utf-8-sig"))
    assert text == POINTS
    assert points_to_file(text).text == POINTS


def test_points_export_is_canonical() -> None:
    text = "' my points\nDEF POS P1=(400,0,300,180,0,180)\nJ1=(0,0,90,0,90,0)\n"
    assert points_from_file("a.POS", text) == text  # kept as written, comment included
    assert points_to_file(text, "G1 team").text == (
        POINTS + "DEF JNT J1=(0.00,0.00,90.00,0.00,90.00,0.00)\n"
    )
    assert points_to_file(text, "G1 team").filename == "G1_team.POS"


def test_broken_points_are_refused_with_a_location() -> None:
    with pytest.raises(TransferError) as err:
        points_from_file("p.POS", "DEF POS P1=(400,0,300,180,0,180)\nDEF POS P2=(1,2\n")
    assert err.value.diagnostics[0].line == 2


@pytest.mark.parametrize("name", ["prog.txt", "prog.mb5", "points.csv", ".MB4", "MB4", ""])
def test_wrong_extensions_are_refused(name: str) -> None:
    with pytest.raises(WrongExtension):
        file_kind(name)


def test_program_and_points_extensions_are_not_interchangeable() -> None:
    with pytest.raises(WrongExtension, match=r"\.MB4"):
        program_from_file("points.POS", NUMBERED)
    with pytest.raises(WrongExtension, match=r"\.POS"):
        points_from_file("prog.MB4", POINTS)
    assert file_kind("C:\\lab\\pick.mb4") is FileKind.PROGRAM


def test_windows_1252_file_is_read() -> None:
    text = "10 ' señal\n20 END\n".encode("cp1252")
    assert program_from_file("a.MB4", text) == "' señal\nEND\n"


def test_workspace_import_replaces_one_half(store: Store) -> None:
    ada = store.accounts.create_user("ada", "kettle-moon-1")
    ws = store.workspaces.personal(ada)
    first = store.workspaces.import_file(ws.id, "pick.MB4", NUMBERED.encode(), base=0, author=ada)
    assert first.revision.reason is SaveReason.IMPORT
    second = store.workspaces.import_file(
        ws.id, "pick.POS", POINTS, base=first.revision.number, author=ada
    )
    state = store.workspaces.state(ws.id)
    assert state.revision == second.revision.number == 2
    assert state.program.startswith("SERVO ON\n")
    assert state.points == POINTS
    assert store.workspaces.export_file(ws.id, FileKind.PROGRAM).text == NUMBERED
    assert store.workspaces.export_file(ws.id, FileKind.POINTS).text == POINTS
    with pytest.raises(WrongExtension):
        store.workspaces.import_file(ws.id, "notes.txt", "hello", base=2, author=ada)
    assert store.workspaces.state(ws.id).revision == 2
