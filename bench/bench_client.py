"""What the safe client costs: upload with the PDIR confirmation, ``--verify``, and STOP while
a request is never answered, on a paced 9600-baud 8E2 line (no controller latency).

Run: ``.venv/bin/python bench/bench_client.py [--lines 200] [--points 20]``

1. **Upload + confirmation**: a re-upload in an open session (as after an edit) with
   `Robot.load_project` and the defaults (slot reset, NEW, LOAD=, ECLR, EMDAT…, the
   ``PARRLNG`` fence before SAVE, SAVE, then ``PDIR`` until the program is listed; the
   PRTVER handshakes went with the first upload of the session), against the line-rate
   minimum ``bytes × 12 / 9600`` of the program and point lines. Aim: within 1.15×.
2. **--verify**: the same upload reading every line and position back (``LISTL``/``LISTP``);
   its cost over (1).
3. **STOP with a request unanswered**: a worker thread waits on a ``JPOSF`` the controller
   never answers; `Robot.stop` is called from another thread. Measured: call → STOP's
   bytes on the wire, and call → ``stop()`` returning (accepted), against one STOP round
   trip on the line (``1;1;STOP`` + ``QoK``, 14 characters).
"""

from __future__ import annotations

import argparse
import contextlib
import threading
import time
from collections.abc import Callable

from bench_link import SETTINGS, check_uploaded, line_minimum, make_program
from melfa.lang.plan import plan_upload
from melfa.link import Link, PacedLink
from melfa.robot import Robot, RobotSettings
from melfa.sim import SimConfig, VirtualController, open_sim_link


class SilentOn(VirtualController):
    """A controller that never answers requests containing ``silent``."""

    def __init__(self, silent: str) -> None:
        super().__init__(SimConfig(strict=False))
        self.silent = silent

    def handle(self, request: bytes | str, now: float) -> bytes:
        text = request.decode("latin-1") if isinstance(request, bytes) else request
        reply = super().handle(request, now)
        return b"" if self.silent in text else reply


class WireClock(PacedLink):
    """Notes when the first byte of each STOP leaves."""

    def __init__(self, inner: Link) -> None:
        super().__init__(inner)
        self.stop_written: float | None = None

    def _write(self, data: bytes) -> None:
        if data.endswith(b"STOP\r") and self.stop_written is None:
            self.stop_written = time.monotonic()
        super()._write(data)


def upload_seconds(
    program: str, points: list[str], *, verify: bool, settings: RobotSettings | None = None
) -> float:
    controller = VirtualController(SimConfig(strict=False))
    robot = Robot(PacedLink(open_sim_link(SETTINGS, controller=controller)), settings)
    robot.connect()
    plan = plan_upload(program, "\n".join(points))
    robot.load_project(plan)  # the program exists already, as after an edit
    try:
        start = time.monotonic()
        report = robot.load_project(plan, verify=verify)
        seconds = time.monotonic() - start
    finally:
        robot.close()
    check_uploaded(controller, program, points)
    assert report.held is not None and report.verified == verify
    return seconds


def stop_latency() -> tuple[float, float]:
    link = WireClock(open_sim_link(SETTINGS, controller=SilentOn("JPOSF")))
    robot = Robot(link)
    robot.connect()
    worker = threading.Thread(target=lambda: _swallow(robot.joints))
    worker.start()
    time.sleep(0.1)  # the JPOSF is on the wire and will never be answered
    start = time.monotonic()
    robot.stop()
    returned = time.monotonic() - start
    assert link.stop_written is not None
    wire = link.stop_written - start
    worker.join()
    robot.close()
    return wire, returned


def _swallow(action: Callable[[], object]) -> None:
    with contextlib.suppress(Exception):  # the unanswered JPOSF times out: expected
        action()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else "")
    parser.add_argument("--lines", type=int, default=200)
    parser.add_argument("--points", type=int, default=20)
    args = parser.parse_args()
    program, points = make_program(args.lines, args.points)
    size, minimum = line_minimum(program, points)
    plain = upload_seconds(program, points, verify=False)
    verified = upload_seconds(program, points, verify=True)
    wire, returned = stop_latency()
    round_trip = 14 * SETTINGS.seconds_per_char
    print(f"9600 baud 8E2, no controller latency; {args.lines}-line program, {args.points} points")
    print(f"line-rate minimum ({size} bytes)          {minimum:6.2f} s")
    print(f"upload + PDIR confirmation               {plain:6.2f} s = {plain / minimum:.2f} ×")
    print(
        f"upload --verify (read back)              {verified:6.2f} s = {verified / minimum:.2f} ×"
        f"  (+{verified - plain:.2f} s, {verified / plain:.2f} × the upload)"
    )
    print(
        f"STOP, JPOSF unanswered: on the wire after {wire * 1000:.1f} ms, accepted after "
        f"{returned * 1000:.1f} ms (one STOP round trip {round_trip * 1000:.1f} ms: "
        f"{returned / round_trip:.2f} ×)"
    )


if __name__ == "__main__":
    main()
