"""The pure parts of recorded runs: the frames' encoding, thinning, and the deviation of a
real path from a simulated one (no I/O, no clock)."""

from __future__ import annotations

import math
from datetime import UTC, datetime, timedelta

import pytest
from hypothesis import given
from hypothesis import strategies as st

from melfa.service.recording_compare import SimSample, SimulatedRun, compare
from melfa.service.recording_frames import EncodingError, Frame, decode, encode
from melfa.store.run_retention import RunAge, to_thin
from melfa.store.thinning import Retention

hundredths = st.integers(-36000, 36000).map(lambda v: v / 100)
axes = st.tuples(*[hundredths] * 6)
frames = st.builds(
    Frame,
    t=st.integers(0, 3_600_000).map(lambda ms: ms / 1000),
    joints=st.none() | axes,
    pose=st.none() | axes,
    line=st.none() | st.integers(1, 5000),
    step=st.none() | st.integers(1, 32767),
    hands=st.tuples(*[st.none() | st.booleans()] * 8),
    alarm=st.none() | st.integers(1, 9999),
    override=st.none() | st.integers(1, 100),
    servo=st.none() | st.booleans(),
    running=st.booleans(),
    paused=st.booleans(),
    moving=st.none() | st.booleans(),
)


@given(st.lists(frames, max_size=40))
def test_frames_survive_encoding(original: list[Frame]) -> None:
    assert decode(encode(original)) == original


def test_a_missing_hand_is_unknown() -> None:
    f = Frame(0.0, None, None, hands=(True, False))
    assert f.hands == (True, False, None, None, None, None, None, None)


def test_values_round_to_the_controllers_resolution() -> None:
    (back,) = decode(encode([Frame(1.23456, (1.234, 0, 0, 0, 0, -0.006), None)]))
    assert back.t == 1.235
    assert back.joints == (1.23, 0, 0, 0, 0, -0.01)


@pytest.mark.parametrize("data", [b"", b"\x02\x00\x00\x00\x00", b"\x01\x01\x00\x00\x00junk"])
def test_other_bytes_are_refused(data: bytes) -> None:
    with pytest.raises(EncodingError):
        decode(data)


def test_a_two_minute_run_at_100_polls_a_second_is_far_under_1_mb() -> None:
    """The budget is 1 MB per 2-minute run at the line's poll rate; the in-memory simulator
    polls about 100 times a second, ten times a real 9600-baud line."""
    run = []
    for i in range(120 * 100):
        t = i / 100
        joints = tuple(round(40 * math.sin(t / (3 + k)) + 10 * k, 2) for k in range(6))
        pose = tuple(round(300 * math.cos(t / (4 + k)), 2) for k in range(6))
        run.append(
            Frame(
                t,
                joints,
                pose,
                line=1 + (i // 300) % 40,
                step=10 * (1 + (i // 300) % 40),
                override=30,
            )
        )
    data = encode(run)
    assert len(data) < 1_000_000
    assert decode(data) == run


# ---- thinning ------------------------------------------------------------------------


NOW = datetime(2026, 11, 20, 12, tzinfo=UTC)


def test_the_newest_runs_are_all_kept() -> None:
    runs = [RunAge(i, NOW - timedelta(minutes=i)) for i in range(5)]
    assert to_thin(runs, NOW, Retention(keep_recent=5)) == []


def test_older_runs_keep_one_per_hour_then_one_per_day() -> None:
    # Two runs in each of the last 30 hours, and two on each of 10 days a month ago.
    hourly = [
        RunAge(i, NOW - timedelta(hours=h, minutes=m))
        for i, (h, m) in enumerate((h, m) for h in range(30) for m in (5, 35))
    ]
    daily = [
        RunAge(100 + i, NOW - timedelta(days=30 + d, hours=h))
        for i, (d, h) in enumerate((d, h) for d in range(10) for h in (1, 3))
    ]
    doomed = set(
        to_thin(hourly + daily, NOW, Retention(keep_recent=4, hourly_for=timedelta(days=7)))
    )
    kept = {r.id for r in hourly + daily} - doomed
    # The four newest, then one per hour, then one per day.
    assert {0, 1, 2, 3} <= kept
    kept_hours = {
        (NOW - r.started).total_seconds() // 3600 for r in hourly if r.id in kept and r.id > 3
    }
    assert len([r for r in hourly if r.id in kept and r.id > 3]) == len(kept_hours)
    assert len([r for r in daily if r.id in kept]) == 10
    assert all(
        r.id not in kept
        or r.started.hour
        == max(x.started.hour for x in daily if x.started.date() == r.started.date())
        for r in daily
    )


def test_a_kept_run_is_never_thinned() -> None:
    runs = [RunAge(i, NOW - timedelta(minutes=i), kept=(i == 9)) for i in range(10)]
    doomed = to_thin(runs, NOW, Retention(keep_recent=1))
    assert 9 not in doomed
    assert sorted(doomed) == list(range(2, 9))  # 0 newest; 1 the newest of its hour


# ---- deviation -----------------------------------------------------------------------


def _sim(
    *points: tuple[float, float, float, int | None], cycle: float | None = 10.0
) -> SimulatedRun:
    return SimulatedRun(
        tuple(SimSample(i * 0.1, x, y, z, line) for i, (x, y, z, line) in enumerate(points)), cycle
    )


def _real(t: float, xyz: tuple[float, float, float], line: int | None) -> Frame:
    return Frame(t, None, (*xyz, 180.0, 0.0, 180.0), line=line)


def test_deviation_is_the_distance_to_the_same_lines_simulated_path() -> None:
    # Line 2 goes along X from 0 to 100 at z=0; line 5 is far away.
    sim = _sim((0, 0, 0, 2), (50, 0, 0, 2), (100, 0, 0, 2), (100, 0, 500, 3), (100, 500, 500, 5))
    real = [_real(0.0, (10, 3, 0), 2), _real(1.0, (60, 0, 4), 2), _real(2.0, (100, 500, 501), 5)]
    result = compare(real, sim, cycle_real=12.5)
    assert result.largest is not None
    assert result.largest.mm == pytest.approx(4.0)
    assert result.largest.line == 2
    assert result.largest.t == 1.0
    assert result.largest.simulated == pytest.approx((60, 0, 0))
    assert result.compared == 3
    assert result.cycle_difference == pytest.approx(2.5)


def test_alignment_is_by_line_not_by_time_or_nearest_anywhere() -> None:
    """A real sample on line 5 that happens to pass near line 2's path is measured against
    line 5's (and its neighbours'): nearest-anywhere would hide the deviation, and time
    (50 s here) means nothing to a run at another speed."""
    sim = _sim(
        (0, 0, 0, 2),
        (100, 0, 0, 2),
        (100, 0, 300, 3),
        (100, 0, 600, 4),
        (400, 0, 600, 5),
        (700, 0, 600, 5),
    )
    real = [_real(50.0, (50, 0, 0), 5)]  # on line 2's path, but line 5 is running
    result = compare(real, sim, None)
    assert result.largest is not None
    assert result.largest.mm == pytest.approx(
        math.dist((50, 0, 0), (100, 0, 300))
    )  # line 4's start


def test_a_line_without_simulated_motion_is_compared_with_the_whole_path() -> None:
    sim = _sim((0, 0, 0, 2), (100, 0, 0, 2))
    result = compare([_real(0.0, (100, 0, 7), 9)], sim, None)
    assert result.largest is not None and result.largest.mm == pytest.approx(7)


def test_samples_without_pose_line_or_run_are_left_out_and_no_sim_means_no_deviation() -> None:
    sim = _sim((0, 0, 0, 2), (100, 0, 0, 2))
    frames = [
        Frame(0.0, None, None, line=2),
        _real(1.0, (0, 50, 0), None),
        Frame(2.0, None, (0, 50, 0, 0, 0, 0), line=2, running=False),
    ]
    assert compare(frames, sim, 3.0).largest is None
    nothing = compare([_real(0.0, (0, 0, 0), 2)], None, 3.0)
    assert (
        nothing.largest is None
        and nothing.cycle_simulated is None
        and nothing.cycle_difference is None
    )


def test_a_stale_line_is_compared_up_to_three_moves_ahead_not_further() -> None:
    """The line comes with every fourth poll: a sample may be a few moves ahead of it."""
    corners = [(0, 0, 0), (100, 0, 0), (100, 100, 0), (0, 100, 0), (0, 100, 100), (0, 0, 100)]
    sim = _sim(*[(*xyz, line) for line, xyz in enumerate(corners, start=2)])
    three_ahead = compare([_real(0.0, (0, 100, 50), 2)], sim, None)  # on line 5→6's segment
    assert three_ahead.largest is not None and three_ahead.largest.mm == pytest.approx(0)
    too_far = compare([_real(0.0, (0, 50, 100), 2)], sim, None)  # line 6→7: four ahead
    assert too_far.largest is not None and too_far.largest.mm > 40
