"""Pack program lines into as few ``EMDAT`` requests as possible.

Rule [DOC S1 p.8; CODE S7; protocol.md §3.8]: items are joined with VT (0x0B); each request,
``1;9;EMDAT`` prefix included, stays within `REQUEST_LIMIT`; a line is never split.

Why greedy is minimal. The lines keep their order, so a packing is a split of the sequence into
consecutive runs, and a run fits iff ``len(prefix) + sum(len) + (count - 1) <= limit``; any
sub-run of a run that fits also fits. Greedy closes a run only when the next line does not fit.
Claim: after *k* runs greedy has packed at least as many lines as any valid packing's first *k*
runs. True for k = 1 (greedy's first run is the longest prefix that fits). If it holds for k,
the optimum's run k+1 starts at or before greedy's next line, so the part of it from greedy's
next line onwards is a sub-run, which fits, so greedy's run k+1 reaches at least as far. Hence
greedy needs no more runs than the optimum. (`tests/protocol/test_emdat.py` also checks this
against an exhaustive dynamic programme.)

>>> [c.request.command for c in chunk_emdat(["10 MOV P1", "20 END"])]
['EMDAT10 MOV P1\\x0b20 END']
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from melfa.protocol.errors import LocalProtocolError
from melfa.protocol.messages import EDIT_SLOT, REQUEST_LIMIT, VT, Request

EMDAT = "EMDAT"


@dataclass(frozen=True)
class EmdatChunk:
    """One EMDAT request and the lines it carries; ``start`` is the index of its first line."""

    request: Request
    start: int
    lines: tuple[str, ...]

    def line_index(self, item: int) -> int:
        """Index in the whole upload of the batch item a refusal names (1-based [GUESS])."""
        return self.start + max(item, 1) - 1


def chunk_emdat(
    lines: Iterable[str], *, robot: int = 1, slot: int = EDIT_SLOT, limit: int = REQUEST_LIMIT
) -> list[EmdatChunk]:
    """Greedy packing of ``lines`` into EMDAT requests of at most ``limit`` bytes each.

    Raises `LocalProtocolError` for a line that is empty, contains VT/CR/LF, or cannot fit
    even alone, naming the line (1-based) and its size.
    """
    if limit > REQUEST_LIMIT:
        raise LocalProtocolError(f"EMDAT limit {limit} exceeds the request limit {REQUEST_LIMIT}")
    prefix = len(f"{robot};{slot};{EMDAT}")
    room = limit - prefix
    chunks: list[EmdatChunk] = []
    batch: list[str] = []
    size = 0
    start = 0

    def close(next_start: int) -> None:
        nonlocal batch, size, start
        if batch:
            chunks.append(
                EmdatChunk(Request(EMDAT + VT.join(batch), robot, slot), start, tuple(batch))
            )
        batch, size, start = [], 0, next_start

    for index, line in enumerate(lines):
        where = f"line {index + 1} ({line[:30]!r})"
        if not line:
            raise LocalProtocolError(f"{where} is empty; EMDAT cannot carry an empty item")
        if any(c in line for c in "\x0b\r\n"):
            raise LocalProtocolError(f"{where} contains VT, CR or LF, which separate items")
        cost = len(line.encode("ascii", errors="replace"))
        if cost > room:
            raise LocalProtocolError(
                f"{where} is {cost} bytes; with the {prefix}-byte prefix a request "
                f"holds at most {room} bytes of one line (limit {limit})"
            )
        extra = cost + (1 if batch else 0)
        if size + extra > room:
            close(index)
            extra = cost
        batch.append(line)
        size += extra
    close(0)
    return chunks
