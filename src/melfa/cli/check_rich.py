"""`melfa check`'s coloured output on a terminal, with source excerpts (Rich).

Apart from `melfa.cli.checking` so that plain output (editors, hooks, pipes) never imports
Rich; `melfa upload` prints its refusals through `print_text` too.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TextIO

from rich.console import Console
from rich.text import Text

from melfa.cli.checking import FileReport, report_lines


def rich_console(stream: TextIO, *, terminal: bool) -> Console:
    return Console(
        file=stream,
        force_terminal=terminal,
        no_color=not terminal,
        highlight=False,
        soft_wrap=True,
        emoji=False,
    )


def print_text(reports: Sequence[FileReport], console: Console) -> None:
    """The findings as `report_lines` lays them out; excerpts only on a terminal."""
    for line in report_lines(reports, excerpts=console.is_terminal):
        console.print(Text.assemble(*((text, style or "") for text, style in line)))
