"""`melfa check`'s coloured output on a terminal, with source excerpts (Rich).

Apart from `melfa.cli.checking` so that plain output (editors, hooks, pipes) never imports
Rich; it prints the lines `checking.report_lines` lays out and imports nothing of
`checking` (which imports this module only on a terminal): the dependency goes one way.
`melfa upload` prints its refusals through `lang_commands.print_text`, on these lines too.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TextIO

from rich.console import Console
from rich.text import Text


def rich_console(stream: TextIO, *, terminal: bool) -> Console:
    return Console(
        file=stream,
        force_terminal=terminal,
        no_color=not terminal,
        highlight=False,
        soft_wrap=True,
        emoji=False,
    )


def print_lines(lines: Iterable[Sequence[tuple[str, str | None]]], console: Console) -> None:
    """Lines of (text, style) segments, as `melfa.cli.checking.report_lines` lays them out."""
    for line in lines:
        console.print(Text.assemble(*((text, style or "") for text, style in line)))
