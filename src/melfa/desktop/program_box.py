"""The *Program and points* panel: where the texts come from (files on this computer or a
workspace of the IDE), the chosen files, Check / Load / Run, and three tabs: the program
with its running line marked, the points, and the check's findings.

Its own module because it is the window's one panel about the student's texts: it shows
what the presenter chose and found, and never acts; the window wires its buttons.
"""

from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import Qt
from PySide6.QtGui import QColor, QFont, QFontDatabase, QTextCursor, QTextFormat
from PySide6.QtWidgets import (
    QAbstractItemView,
    QComboBox,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QPlainTextEdit,
    QPushButton,
    QTabWidget,
    QTextEdit,
    QTreeWidget,
    QTreeWidgetItem,
    QVBoxLayout,
    QWidget,
)

from melfa.desktop.api import CheckResult, Severity, WorkspaceInfo
from melfa.desktop.files import ChosenFile, FileKind
from melfa.desktop.words import Loaded, count, file_line
from melfa.live.messages import StateOut
from melfa.vocab.activity import Activity

FILES_SOURCE = "Files on this computer"


class RefreshingCombo(QComboBox):
    """A combo box that asks for a fresh list each time it opens (new workspaces appear)."""

    def __init__(self, refresh: Callable[[], object]) -> None:
        super().__init__()
        self._refresh = refresh

    def showPopup(self) -> None:  # noqa: N802 (Qt's name)
        self._refresh()
        super().showPopup()


class ProgramBox(QGroupBox):
    """The panel; ``refresh_workspaces`` is asked each time the source list opens."""

    def __init__(self, refresh_workspaces: Callable[[], object]) -> None:
        super().__init__("Program and points")
        layout = QVBoxLayout(self)
        layout.setSpacing(4)
        grid = QGridLayout()
        grid.setColumnStretch(1, 1)
        self.source_box = RefreshingCombo(refresh_workspaces)
        self.source_box.setAccessibleName("Load from files or from a workspace")
        self.source_box.setToolTip("Files on this computer, or a workspace you wrote in the IDE")
        self.source_box.addItem(FILES_SOURCE, None)
        source_label = QLabel("&From:")
        source_label.setBuddy(self.source_box)
        grid.addWidget(source_label, 0, 0)
        grid.addWidget(self.source_box, 0, 1, 1, 2)
        self.program_edit, self.program_button = self._file_row(grid, 1, FileKind.PROGRAM)
        self.points_edit, self.points_button = self._file_row(grid, 2, FileKind.POINTS)
        layout.addLayout(grid)

        buttons = QHBoxLayout()
        self.check_button = QPushButton("Chec&k")
        self.check_button.setToolTip("Check the program against the points (sends nothing)")
        self.load_button = QPushButton("&Load into robot")
        self.load_button.setObjectName("primary")
        self.load_button.setToolTip("Check, then load the program and its points into the robot")
        self.run_button = QPushButton("▶  &Run program")
        self.run_button.setObjectName("primary")
        self.run_button.setToolTip("Run the program loaded into the robot")
        buttons.addWidget(self.check_button)
        buttons.addStretch(1)
        buttons.addWidget(self.load_button)
        buttons.addWidget(self.run_button)
        layout.addLayout(buttons)

        self.tabs = QTabWidget()
        mono = QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont)
        self.program_view = QPlainTextEdit()
        self.points_view = QPlainTextEdit()
        for view, empty in (
            (self.program_view, "Choose a program file to see it here."),
            (self.points_view, "Choose a points file to see it here."),
        ):
            view.setReadOnly(True)
            view.setFont(mono)
            view.setPlaceholderText(empty)
            view.setLineWrapMode(QPlainTextEdit.LineWrapMode.NoWrap)
        self.check_label = QLabel("Check results: not checked yet")
        self.check_label.setObjectName("muted")
        self.diagnostics = QTreeWidget()
        self.diagnostics.setColumnCount(3)
        self.diagnostics.setHeaderLabels(["Where", "Severity", "Message"])
        self.diagnostics.setRootIsDecorated(False)
        self.diagnostics.setAlternatingRowColors(True)
        self.diagnostics.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        header = self.diagnostics.header()
        header.setSectionResizeMode(0, QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(1, QHeaderView.ResizeMode.ResizeToContents)
        header.setStretchLastSection(True)
        check_page = QWidget()
        check_layout = QVBoxLayout(check_page)
        check_layout.setContentsMargins(6, 6, 6, 6)
        check_layout.addWidget(self.check_label)
        check_layout.addWidget(self.diagnostics, 1)
        self.tabs.addTab(self.program_view, "Program")
        self.tabs.addTab(self.points_view, "Points")
        self.tabs.addTab(check_page, "Check results")
        layout.addWidget(self.tabs, 1)
        self._followed_line: int | None = None
        """The running line last scrolled into view (scrolled again only when it moves)."""

    @staticmethod
    def _file_row(grid: QGridLayout, row: int, kind: FileKind) -> tuple[QLineEdit, QPushButton]:
        label = QLabel(  # Alt+P / Alt+O reach the Choose… buttons from the keyboard
            f"&Program ({kind.value}):" if kind is FileKind.PROGRAM else f"P&oints ({kind.value}):"
        )
        edit = QLineEdit()
        edit.setReadOnly(True)
        edit.setPlaceholderText("No file chosen")
        edit.setAccessibleName(f"{kind.label} file")
        button = QPushButton("Choose…")
        button.setAccessibleName(f"Choose {kind.label}")
        label.setBuddy(button)
        grid.addWidget(label, row, 0)
        grid.addWidget(edit, row, 1)
        grid.addWidget(button, row, 2)
        return edit, button

    def show_busy(self, idle: bool, has_program: bool) -> None:
        """Commands wait while one runs; choosing a file is local and always allowed (the
        command uses its own copy), but only when the texts come from files."""
        self.run_button.setEnabled(idle)
        from_files = self.source_box.currentData() is None
        self.program_button.setEnabled(from_files)
        self.points_button.setEnabled(from_files)
        self.source_box.setEnabled(idle)
        self.check_button.setEnabled(idle and has_program)
        self.load_button.setEnabled(idle and has_program)

    def show_files(self, program: ChosenFile | None, points: ChosenFile | None) -> None:
        for chosen, edit, view in (
            (program, self.program_edit, self.program_view),
            (points, self.points_edit, self.points_view),
        ):
            if chosen is None:
                edit.clear()
                edit.setToolTip("")
                view.clear()
                continue
            lines = len(chosen.text.splitlines())
            edit.setText(f"{chosen.name}  ·  {count(lines, 'line')}")
            edit.setCursorPosition(0)
            # The whole path on hover, never clipped.
            edit.setToolTip(str(chosen.path) if chosen.workspace is None else chosen.name)
            if view.toPlainText() != chosen.text:
                view.setPlainText(chosen.text)
                self.tabs.setCurrentWidget(view)  # show what was just chosen

    def show_workspaces(self, workspaces: tuple[WorkspaceInfo, ...]) -> None:
        box = self.source_box
        chosen = box.currentData()
        box.blockSignals(True)  # a new list is not a new choice
        box.clear()
        box.addItem(FILES_SOURCE, None)
        for workspace in workspaces:
            shared = " (shared)" if workspace.shared else ""
            box.addItem(f"Workspace: {workspace.name}{shared}", workspace.id)
        box.setCurrentIndex(max(0, box.findData(chosen)) if chosen is not None else 0)
        box.blockSignals(False)

    def show_check(self, result: CheckResult) -> None:
        self.diagnostics.clear()
        for source, diags in (("", result.program), ("points ", result.points)):
            for d in diags:
                item = QTreeWidgetItem(
                    [f"{source}{d.line}:{d.column}", d.severity.value, d.message]
                )
                if d.suggestion:
                    item.setToolTip(2, d.suggestion)
                if d.severity is Severity.ERROR:
                    item.setForeground(1, Qt.GlobalColor.darkRed)
                    font = QFont(item.font(1))
                    font.setBold(True)
                    item.setFont(1, font)
                self.diagnostics.addTopLevelItem(item)
        errors = len(result.program_errors) + len(result.points_errors)
        total = len(result.program) + len(result.points)
        self.tabs.setTabText(2, f"Check results ({total})" if total else "Check results")
        if errors:
            self.tabs.setCurrentIndex(2)
        self.check_label.setText(
            "Check results: no findings"
            if not total
            else f"Check results: {count(errors, 'error')}, "
            f"{count(total - errors, 'warning or note')}"
        )

    def mark_line(self, state: StateOut, loaded: Loaded | None, program: ChosenFile | None) -> None:
        """Highlight the running (or paused) line in the program, when it is the loaded file,
        and scroll it into view when it changes (a long program's line is followed)."""
        shows = state.activity in (Activity.RUNNING, Activity.PAUSED) or bool(
            state.running and state.line
        )
        line = file_line(state.line, loaded) if shows else None
        same_file = loaded is not None and program is not None
        same_file = same_file and program.path.name == loaded.name  # type: ignore[union-attr]
        selections: list[QTextEdit.ExtraSelection] = []
        if line is not None and same_file:
            block = self.program_view.document().findBlockByNumber(line - 1)
            if block.isValid():
                mark = QTextEdit.ExtraSelection()
                mark.format.setBackground(QColor("#fff59d"))
                mark.format.setProperty(QTextFormat.Property.FullWidthSelection, True)
                mark.cursor = QTextCursor(block)
                selections.append(mark)
                if line != self._followed_line:
                    self.program_view.setTextCursor(QTextCursor(block))
                    self.program_view.ensureCursorVisible()
        self._followed_line = line if selections else None
        self.program_view.setExtraSelections(selections)


__all__ = ["FILES_SOURCE", "ProgramBox", "RefreshingCombo"]
