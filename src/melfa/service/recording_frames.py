"""A recorded run's samples (`Frame`) and their compact encoding (`encode` / `decode`).

A frame is what one state snapshot said while a program ran on a shared robot: the time
since the run began (the service's clock), joints, pose, the running line of the student's
own text (and the controller's step), hands, alarm, override, servo and run flags.

The encoding is columnar: every field becomes one integer column at the controller's own
resolution (time in ms, joints and pose in hundredths, as JPOSF/PPOSF report them), each
column is stored as differences from the previous frame (int32, little-endian) and the
whole is zlib-compressed. A still arm or a line that does not change costs almost nothing;
a 2-minute run polled 100 times a second is tens of kilobytes (README, `bench_runs.py`).
Values round to the resolution above; nothing else is lost. Unknown values (no joints yet,
a ``****`` position) are kept as unknown through a flags column.

Pure: no I/O, no clock.

>>> f = Frame(0.5, (1.0, 2.0, 3.0, 4.0, 5.0, 6.0), None, line=3, step=30)
>>> decode(encode([f])) == [f]
True
"""

from __future__ import annotations

import enum
import zlib
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

HANDS = 8
"""Hands 1…8, as the snapshot carries them."""
VERSION = 1
"""The first byte of an encoding; a later format gets a new number."""
_AXES = 6


class EncodingError(ValueError):
    """Bytes that are not a recording this melfa can read."""


class Flag(enum.IntFlag):
    """Which values of a frame are known, and the run's boolean facts."""

    JOINTS = 1
    POSE = 2
    LINE = 4
    STEP = 8
    OVERRIDE = 16
    SERVO_KNOWN = 32
    SERVO = 64
    RUNNING = 128
    PAUSED = 256
    MOVING_KNOWN = 512
    MOVING = 1024
    ALARM = 2048


@dataclass(frozen=True, slots=True)
class Frame:
    """One sample of a run (the fields of `melfa.service.events.StateSnapshot` a replay
    needs). ``t``: seconds since the run began; ``line``: the student's line; ``hands``:
    1…8, True open, False closed, None unknown (missing hands are unknown)."""

    t: float
    joints: tuple[float, ...] | None
    pose: tuple[float, ...] | None
    line: int | None = None
    step: int | None = None
    hands: tuple[bool | None, ...] = ()
    alarm: int | None = None
    override: int | None = None
    servo: bool | None = None
    running: bool = True
    paused: bool = False
    moving: bool | None = None

    def __post_init__(self) -> None:
        if len(self.hands) < HANDS:
            object.__setattr__(self, "hands", (*self.hands, *(None,) * (HANDS - len(self.hands))))

    @property
    def xyz(self) -> tuple[float, float, float] | None:
        """The TCP's X, Y, Z (mm), when the pose is known."""
        if self.pose is None:
            return None
        return (self.pose[0], self.pose[1], self.pose[2])


_COLUMNS = 1 + _AXES + _AXES + 6
"""t, joints, pose, line, step, hands, alarm, override, flags."""


def _hands_code(hands: tuple[bool | None, ...]) -> int:
    code = 0
    for i, h in enumerate(hands[:HANDS]):
        code |= (0 if h is None else 1 if h else 2) << (2 * i)
    return code


def _hands_of(code: int) -> tuple[bool | None, ...]:
    out: list[bool | None] = []
    for i in range(HANDS):
        v = (code >> (2 * i)) & 3
        out.append(None if v == 0 else v == 1)
    return tuple(out)


def _row(f: Frame, last: list[int]) -> list[int]:
    """One frame as integers; an unknown value repeats the last one (its delta is 0)."""
    flags = Flag(0)
    row = [round(f.t * 1000)]
    if f.joints is not None:
        flags |= Flag.JOINTS
        row += [round(v * 100) for v in f.joints[:_AXES]]
    else:
        row += last[1 : 1 + _AXES]
    if f.pose is not None:
        flags |= Flag.POSE
        row += [round(v * 100) for v in f.pose[:_AXES]]
    else:
        row += last[1 + _AXES : 1 + 2 * _AXES]
    for value, flag in ((f.line, Flag.LINE), (f.step, Flag.STEP)):
        if value is not None:
            flags |= flag
        row.append(value if value is not None else 0)
    row.append(_hands_code(f.hands))
    if f.alarm is not None:
        flags |= Flag.ALARM
    row.append(f.alarm or 0)
    if f.override is not None:
        flags |= Flag.OVERRIDE
    row.append(f.override or 0)
    if f.servo is not None:
        flags |= Flag.SERVO_KNOWN | (Flag.SERVO if f.servo else 0)
    if f.running:
        flags |= Flag.RUNNING
    if f.paused:
        flags |= Flag.PAUSED
    if f.moving is not None:
        flags |= Flag.MOVING_KNOWN | (Flag.MOVING if f.moving else 0)
    row.append(int(flags))
    return row


def encode(frames: Sequence[Frame]) -> bytes:
    """The frames as compact bytes (see the module doc)."""
    rows: list[list[int]] = []
    last = [0] * _COLUMNS
    for f in frames:
        last = _row(f, last)
        rows.append(last)
    table = np.array(rows, dtype=np.int64).reshape(len(rows), _COLUMNS)
    deltas = np.diff(table, axis=0, prepend=np.zeros((1, _COLUMNS), dtype=np.int64))
    if deltas.size and (deltas.max() > 2**31 - 1 or deltas.min() < -(2**31)):
        raise EncodingError("a value changed by more than a recording can hold")
    body = deltas.T.astype("<i4").tobytes()  # column by column: like values together
    return bytes([VERSION]) + len(rows).to_bytes(4, "little") + zlib.compress(body, 9)


def decode(data: bytes) -> list[Frame]:
    """The frames of `encode`'s bytes; `EncodingError` for anything else."""
    if len(data) < 5 or data[0] != VERSION:
        raise EncodingError("not a melfa run recording (or a newer format)")
    count = int.from_bytes(data[1:5], "little")
    try:
        body = zlib.decompress(data[5:])
    except zlib.error as exc:
        raise EncodingError(f"damaged recording: {exc}") from None
    if len(body) != count * _COLUMNS * 4:
        raise EncodingError("damaged recording: wrong length")
    deltas = np.frombuffer(body, dtype="<i4").reshape(_COLUMNS, count).T.astype(np.int64)
    table = np.cumsum(deltas, axis=0).tolist()
    frames: list[Frame] = []
    for row in table:
        flags = Flag(row[-1])
        joints = tuple(v / 100 for v in row[1 : 1 + _AXES]) if Flag.JOINTS in flags else None
        pose = (
            tuple(v / 100 for v in row[1 + _AXES : 1 + 2 * _AXES]) if Flag.POSE in flags else None
        )
        line, step, hands, alarm, override = row[1 + 2 * _AXES : 1 + 2 * _AXES + 5]
        frames.append(
            Frame(
                row[0] / 1000,
                joints,
                pose,
                line=line if Flag.LINE in flags else None,
                step=step if Flag.STEP in flags else None,
                hands=_hands_of(hands),
                alarm=alarm if Flag.ALARM in flags else None,
                override=override if Flag.OVERRIDE in flags else None,
                servo=(Flag.SERVO in flags) if Flag.SERVO_KNOWN in flags else None,
                running=Flag.RUNNING in flags,
                paused=Flag.PAUSED in flags,
                moving=(Flag.MOVING in flags) if Flag.MOVING_KNOWN in flags else None,
            )
        )
    return frames


__all__ = ["HANDS", "VERSION", "EncodingError", "Flag", "Frame", "decode", "encode"]
