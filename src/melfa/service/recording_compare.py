"""How far a real run went from its simulated one: the largest TCP deviation and the
cycle-time difference (`compare`).

**Alignment: by line, not by time.** The real arm runs at the operation panel's override
and waits on a 9600-baud line; the simulated run (pre-flight) at its own speed. The same
instant of two runs is therefore not the same place on the path, and comparing by time
would report the speed difference as a deviation. Instead every real sample is compared
with the simulated path *of the line the controller said was running* (the student's line,
through the loaded step map): its distance to the nearest point of that line's simulated
segments. The running line is read with STATE only every fourth poll, so a sample taken
after a line change may still carry an older line: the segments of the simulated moves
just before (`VISITS_BEFORE`) and after (`VISITS_AFTER`) each visit of that line count
too. A line with no
simulated motion (a ``DLY``, a ``WAIT``, a line the simulation never reached) is compared
with the whole simulated path. Samples without a pose or a line, and those taken while the
program was not running, are left out.

The timing is compared on its own: the real cycle time (RUN accepted to the STATE that
showed the program ended, to within one STATE poll) against the simulated one.

Pure: no I/O, no clock.
"""

from __future__ import annotations

import json
import zlib
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from melfa.service.recording_frames import Frame

VISITS_BEFORE = 1
"""Simulated moves before the running line's that a sample is also compared with (its
joints are read just before the STATE that named the line)."""
VISITS_AFTER = 3
"""And after it: the line is read with every fourth poll, about 1.2 s apart on the real
9600-baud line, and the arm may be a few short moves further by the next read (the
thesis's pyramid on a paced line: 19.8 mm with one move either side, 1.1 mm on the bare
link, where the line is read ten times as often)."""


@dataclass(frozen=True, slots=True)
class SimSample:
    """A sample of the simulated TCP path (pre-flight's ``path``): time (s), X, Y, Z (mm),
    the student's line."""

    t: float
    x: float
    y: float
    z: float
    line: int | None


@dataclass(frozen=True, slots=True)
class SimulatedRun:
    """The simulated run a real one is compared with: its TCP path and cycle time."""

    path: tuple[SimSample, ...]
    cycle_time: float | None


@dataclass(frozen=True, slots=True)
class Deviation:
    """The largest distance found: where (real sample's time and line), the real TCP and
    the nearest simulated point."""

    mm: float
    t: float
    line: int | None
    real: tuple[float, float, float]
    simulated: tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class Comparison:
    """What the run report says about real against simulated."""

    largest: Deviation | None
    """None: nothing to compare (no simulated path, or no sample with a pose and line)."""
    compared: int
    """Real samples compared."""
    cycle_real: float | None
    cycle_simulated: float | None

    @property
    def cycle_difference(self) -> float | None:
        """Real minus simulated (s); None when either is unknown."""
        if self.cycle_real is None or self.cycle_simulated is None:
            return None
        return self.cycle_real - self.cycle_simulated


def _segments(path: Sequence[SimSample]) -> tuple[np.ndarray, np.ndarray, dict[int, np.ndarray]]:
    """Segment starts and ends (n×3) and, per line, which segments are its candidates."""
    xyz = np.array([(s.x, s.y, s.z) for s in path], dtype=float).reshape(-1, 3)
    if len(path) == 1:  # one sample: a segment of length 0
        a, b = xyz, xyz
    else:
        a, b = xyz[:-1], xyz[1:]
    # Visits: runs of consecutive samples on one line; a segment belongs to the visit of
    # its end sample (and of its start: a segment joining two visits is in both).
    visit_of: list[int] = []
    visit_lines: list[int | None] = []
    for s in path:
        if not visit_lines or visit_lines[-1] != s.line:
            visit_lines.append(s.line)
        visit_of.append(len(visit_lines) - 1)
    segments_of: dict[int, set[int]] = {}
    for i in range(len(a)):
        for v in (visit_of[i], visit_of[min(i + 1, len(path) - 1)]):
            segments_of.setdefault(v, set()).add(i)
    by_line: dict[int, set[int]] = {}
    for v, line in enumerate(visit_lines):
        if line is None:
            continue
        wanted = by_line.setdefault(line, set())
        for near in range(v - VISITS_BEFORE, v + VISITS_AFTER + 1):
            wanted |= segments_of.get(near, set())
    return a, b, {line: np.array(sorted(ix), dtype=int) for line, ix in by_line.items()}


def _nearest(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[float, np.ndarray]:
    """Distance from ``p`` to the nearest of the segments a→b, and that point."""
    ab = b - a
    length2 = np.einsum("ij,ij->i", ab, ab)
    safe = np.where(length2 > 0, length2, 1.0)
    u = np.clip(np.einsum("ij,ij->i", p - a, ab) / safe, 0.0, 1.0)
    u = np.where(length2 > 0, u, 0.0)
    points = a + ab * u[:, None]
    d = np.linalg.norm(points - p, axis=1)
    best = int(np.argmin(d))
    return float(d[best]), points[best]


def compare(
    frames: Sequence[Frame], simulated: SimulatedRun | None, cycle_real: float | None
) -> Comparison:
    """The largest TCP deviation of ``frames`` from ``simulated`` (aligned by line, see the
    module doc) and the two cycle times."""
    cycle_sim = simulated.cycle_time if simulated is not None else None
    if simulated is None or not simulated.path:
        return Comparison(None, 0, cycle_real, cycle_sim)
    a, b, by_line = _segments(simulated.path)
    everything = np.arange(len(a))
    largest: Deviation | None = None
    compared = 0
    for f in frames:
        xyz = f.xyz
        if xyz is None or f.line is None or not f.running:
            continue
        ix = by_line.get(f.line, everything)
        p = np.array(xyz, dtype=float)
        d, q = _nearest(p, a[ix], b[ix])
        compared += 1
        if largest is None or d > largest.mm:
            largest = Deviation(d, f.t, f.line, xyz, (float(q[0]), float(q[1]), float(q[2])))
    return Comparison(largest, compared, cycle_real, cycle_sim)


def simulated_run(
    path: Iterable[tuple[float, float, float, float, int | None]], cycle_time: float | None
) -> SimulatedRun:
    """From pre-flight's path samples ``(t, x, y, z, line)``."""
    return SimulatedRun(tuple(SimSample(*p) for p in path), cycle_time)


def pack(run: SimulatedRun) -> bytes:
    """A simulated run as stored (zlib'd JSON, mm to 0.01)."""
    rows = [[round(s.t, 3), round(s.x, 2), round(s.y, 2), round(s.z, 2), s.line] for s in run.path]
    return zlib.compress(json.dumps({"cycle_time": run.cycle_time, "path": rows}).encode(), 9)


def unpack(data: bytes) -> SimulatedRun:
    """The inverse of `pack`."""
    value = json.loads(zlib.decompress(data))
    return simulated_run((tuple(row) for row in value["path"]), value["cycle_time"])


__all__ = [
    "Comparison",
    "Deviation",
    "SimSample",
    "SimulatedRun",
    "compare",
    "pack",
    "simulated_run",
    "unpack",
]
