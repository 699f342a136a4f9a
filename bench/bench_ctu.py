"""ctu-mitsubishi's time per request against `melfa sim` on a pty paced at 38400 8E2 with the
controller's 0.1 s latency: its ``readline()`` waits for LF, so with CTERM232 = 0 (replies
end in CR only) every request waits out its 1 s serial timeout; with CTERM232 = 1 (CR LF,
``melfa sim --cterm 1``) it returns when the reply has arrived.

Run: ``.venv/bin/python bench/bench_ctu.py``

The sequence is the client's own: ``initialize`` (stop_robot, CNTLON, OVRD=25, RUN of the
resident program, get_q), ``move_to_q``, ``wait_for_motion_stop``, ``stop_robot``, with the
resident program of ``examples/ctu_mitsubishi/MOVEIT.MB4``.
"""

from __future__ import annotations

import statistics
import time
from pathlib import Path
from typing import Any

import numpy as np

from melfa.sim import Pacing, PtyServer, SimConfig, VirtualController
from melfa.sim.config import Terminator

MOVEIT = Path(__file__).resolve().parents[1] / "examples" / "ctu_mitsubishi" / "MOVEIT.MB4"


def per_request(cterm: Terminator) -> list[float]:
    """Seconds each of the client's requests took, in order."""
    import ctu_mitsubishi  # type: ignore[import-untyped]

    controller = VirtualController(
        SimConfig(cterm=cterm, strict=True), programs={"MOVEIT": MOVEIT.read_text()}
    )
    for request in (b"1;1;CNTLON\r", b"1;1;SRVON\r", b"1;1;CNTLOFF\r"):
        controller.handle(request, 0.0)  # the operator's servo-on at the panel
    times: list[float] = []
    with PtyServer(controller, pacing=Pacing.for_baud(38400)) as server:
        robot: Any = ctu_mitsubishi.Rv6s(port=server.new_port())
        send = robot._send_and_receive

        def timed(message: str) -> str:
            start = time.perf_counter()
            reply = str(send(message))
            times.append(time.perf_counter() - start)
            return reply

        robot._send_and_receive = timed
        robot.initialize()
        robot.move_to_q(np.deg2rad([10.0, 5.0, 95.0, 0.0, 80.0, 0.0]))
        robot.wait_for_motion_stop(timeout=60)
        robot.stop_robot()
        robot.close_connection()
    return times


def main() -> None:
    for cterm in (Terminator.CR, Terminator.CRLF):
        times = per_request(cterm)
        print(
            f"CTERM232={cterm.value} ({'CR' if cterm is Terminator.CR else 'CR LF'}): "
            f"{len(times)} requests, median {statistics.median(times):.3f} s, "
            f"min {min(times):.3f} s, max {max(times):.3f} s"
        )


if __name__ == "__main__":
    main()
