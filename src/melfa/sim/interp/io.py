"""The controller's general-purpose I/O as a program sees it (``M_IN``, ``M_OUT`` …).

Inputs are set from outside the program (tests, the CLI, later the UI) with `set_input`;
outputs are written by the program and read by anyone. Bits are numbered as on the
controller (0…); a multi-bit read (``M_IN8(n)``, ``M_INW(n)``) takes `width` bits starting
at bit n, lowest bit first [melfa-basic-iv.md §4.7].
"""

from __future__ import annotations

from collections.abc import Callable


class IOState:
    """Input and output bits of one controller; changes notify `listeners`."""

    def __init__(self) -> None:
        self._inputs: dict[int, int] = {}
        self._outputs: dict[int, int] = {}
        self.listeners: list[Callable[[str, int, int], None]] = []
        """Called with ("in"|"out", bit, value) whenever a bit changes."""
        self.before_read: Callable[[], None] | None = None
        """Called before a program reads an input (a simulated cell's sensors set theirs)."""

    # --- inputs -------------------------------------------------------------------------
    def input(self, bit: int) -> int:
        if self.before_read is not None:
            self.before_read()
        return self._inputs.get(bit, 0)

    def set_input(self, bit: int, value: int | bool) -> None:
        """Drive one input bit (what a sensor or the operator would do)."""
        self._set(self._inputs, "in", bit, 1 if value else 0)

    def read_inputs(self, start: int, width: int) -> int:
        if self.before_read is not None:
            self.before_read()
        return _read(self._inputs, start, width)

    def set_inputs(self, start: int, width: int, value: int) -> None:
        for i in range(width):
            self._set(self._inputs, "in", start + i, (value >> i) & 1)

    # --- outputs ------------------------------------------------------------------------
    def output(self, bit: int) -> int:
        return self._outputs.get(bit, 0)

    def set_output(self, bit: int, value: int | bool) -> None:
        self._set(self._outputs, "out", bit, 1 if value else 0)

    def read_outputs(self, start: int, width: int) -> int:
        return _read(self._outputs, start, width)

    def write_outputs(self, start: int, width: int, value: int) -> None:
        for i in range(width):
            self._set(self._outputs, "out", start + i, (value >> i) & 1)

    def inputs(self) -> dict[int, int]:
        """Every input bit that is on (a copy)."""
        return {k: v for k, v in self._inputs.items() if v}

    def outputs(self) -> dict[int, int]:
        """Every output bit that is on (a copy)."""
        return {k: v for k, v in self._outputs.items() if v}

    def clear_outputs(self) -> None:
        for bit in list(self._outputs):
            self.set_output(bit, 0)

    def _set(self, table: dict[int, int], kind: str, bit: int, value: int) -> None:
        if bit < 0:
            raise ValueError(f"I/O bit numbers start at 0, got {bit}")
        if table.get(bit, 0) != value:
            table[bit] = value
            for listener in self.listeners:
                listener(kind, bit, value)


def _read(table: dict[int, int], start: int, width: int) -> int:
    value = 0
    for i in range(width):
        if table.get(start + i, 0):
            value |= 1 << i
    return value


def parse_input(text: str) -> tuple[int, int]:
    """`N=V` (input signal N to value V, 0 or 1) -> (N, V); ValueError with what is wrong.

    >>> parse_input("3=1"), parse_input(" 12 = 0 ")
    ((3, 1), (12, 0))
    """
    bit, sep, value = text.partition("=")
    bit, value = bit.strip(), value.strip()
    if not sep or not bit.isdigit() or value not in ("0", "1"):
        raise ValueError(f"{text!r} is not N=V (input signal number N ≥ 0, value 0 or 1)")
    return int(bit), int(value)


def parse_feed(text: str) -> tuple[int, str]:
    """`N=TEXT` (a line the program's ``INPUT #N`` reads) -> (N, TEXT); ValueError if not.

    >>> parse_feed("1=12,3.5,OK"), parse_feed(" 2 = ")
    ((1, '12,3.5,OK'), (2, ''))
    """
    channel, sep, line = text.partition("=")
    channel = channel.strip()
    if not sep or not channel.isdigit():
        raise ValueError(f"{text!r} is not N=TEXT (file number N, the line INPUT #N reads)")
    return int(channel), line.strip()


def parse_pose(text: str) -> tuple[tuple[float, ...], int | None, int | None]:
    """`X,Y,Z,A,B,C[,FL1[,FL2]]` (mm and degrees, where the arm starts), or the controller's
    form ``(X,Y,Z,A,B,C)(FL1,FL2)`` -> (six numbers, FL1, FL2: None when not given);
    ValueError with what is wrong.

    >>> parse_pose("400, 0, 645, 180, 0, 180")
    ((400.0, 0.0, 645.0, 180.0, 0.0, 180.0), None, None)
    >>> parse_pose("(+400.00,+0.00,+645.00,+180.00,+0.00,+180.00)(6,0)")
    ((400.0, 0.0, 645.0, 180.0, 0.0, 180.0), 6, 0)
    """
    parts = [p.strip() for p in text.replace(")(", ",").strip().strip("()").split(",")]
    numbers: list[float] = []
    flags: list[int] = []
    try:
        numbers = [float(p) for p in parts[:6]]
        flags = [int(p, 0) if not p.upper().startswith("&H") else int(p[2:], 16) for p in parts[6:]]
    except ValueError:
        numbers = []
    if len(numbers) != 6 or len(flags) > 2:
        raise ValueError(
            f"{text!r} is not a position X,Y,Z,A,B,C (mm and degrees), optionally with its "
            "flags FL1,FL2"
        )
    return tuple(numbers), (flags[0] if flags else None), (flags[1] if len(flags) > 1 else None)


def parse_joints(text: str) -> tuple[float, ...]:
    """`J1,J2,J3,J4,J5,J6` in degrees (where the arm starts) -> six numbers; ValueError.

    >>> parse_joints("0, 30, 90, 0, 60, 0")
    (0.0, 30.0, 90.0, 0.0, 60.0, 0.0)
    """
    parts = [p.strip() for p in text.split(",")]
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        values = ()
    if len(values) != 6:
        raise ValueError(f"{text!r} is not six joint angles in degrees, J1,J2,J3,J4,J5,J6")
    return values
