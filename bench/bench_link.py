"""Upload and polling speed on a simulated 9600-baud 8E2 line, against two yardsticks.

Run: ``.venv/bin/python bench/bench_link.py [--latency 0.1] [--lines 200] [--points 20]``

Everything runs in one process on the same link: the virtual controller in memory behind
`melfa.link.PacedLink`, which delays every byte by 12 bits / 9600 baud = 1.25 ms each way
(and, with ``--latency``, adds controller processing time before each reply; the S21
traces show 0.1–0.15 s, prior-art.md §5). Measured in one run:

1. **Line-rate minimum**: the program and point lines, one separator each, sent once:
   ``bytes × 12 / 9600``. Nothing can upload faster over this line.
2. **melfa**: `Robot.load_project` (one session, program + points in one LOAD…SAVE) and,
   for comparison, `upload_program` + `upload_points` (two LOAD…SAVE sessions), without the
   PRTVER handshakes, and with two EMDAT requests in flight (``emdat_window=2``, a [GUESS]
   about the controller's input buffering, off by default).
3. **Thesis replay** (protocol.md §4.2, S7 ``execute_node.cpp``/``melfa.cpp``): for the
   program and then again for the points, a new connection running "connect for load"
   (OPEN=NARCUSR, PARRLNG, PDIRTOP, PPOSF, PARMEXTL, KEYWDptest), then NEW, LOAD=1,
   PRTVERLISTL, PRTVEREMDAT, ``1;9;LISTL<``, EMDAT of bare line numbers (clearing), EMDAT of
   the lines (S7 packs up to 255 characters), SAVE, CLOSE. What we do *not* replay, to be
   generous to the thesis: the 2 s / 1 s sleeps of its motion init/deinit (initRobot's SRVON
   wait and the SRVOFF wait are not part of the load path in §4.2), the port open/close time
   of a real adapter, and S7's off-by-one chunking slips. A second row adds initRobot/deinit
   around each of the two operations (as §4.2 says the thesis did for every command), for
   an upper bound.
4. **JPOSF polling**: back-to-back `Robot.joints()` against the line bound
   ``1 / ((request + reply bytes) × 12 / 9600)``; the thesis reconnected for each read
   (OPEN, JPOSF, CLOSE).

The aims: melfa within 1.2× of the line-rate minimum, and ≥ 2× faster than the thesis.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

from melfa.link import Link, LinkSettings, PacedLink
from melfa.protocol import Request, chunk_emdat, encode_reply
from melfa.robot import Robot, RobotSettings, point_items, program_items
from melfa.sim import VirtualController, open_sim_link

SETTINGS = LinkSettings()  # 9600 8E2


def make_program(lines: int, points: int) -> tuple[str, list[str]]:
    """A realistic pick-and-place style program of ``lines`` steps and its points."""
    body = [
        "SERVO ON",
        "OVRD 50",
        "SPD 200",
        "HOPEN 1",
        "M1=0",
    ]
    templates = [
        "MOV P{p},-50",
        "MVS P{p}",
        "HCLOSE 1",
        "DLY 0.3",
        "MVS P{p},-50",
        "MOV P{q}",
        "HOPEN 1",
        "M1=M1+1",
    ]
    i = 0
    while len(body) < lines - 1:
        template = templates[i % len(templates)]
        body.append(template.format(p=i % points + 1, q=(i + 7) % points + 1))
        i += 1
    body.append("END")
    program = "\n".join(f"{10 * (n + 1)} {text}" for n, text in enumerate(body))
    pts = [
        f"P{k}=({300 + 7.25 * k:.2f},{-150 + 13.5 * k:.2f},{450 - 4.75 * k:.2f},"
        f"180.00,0.00,{180 - k:.2f})(7,0)"
        for k in range(1, points + 1)
    ]
    return program, pts


def paced(controller: VirtualController, latency: float) -> Link:
    return PacedLink(open_sim_link(SETTINGS, controller=controller), latency=latency)


def timed(action: Callable[[], object]) -> float:
    """Wall-clock seconds of one call."""
    start = time.monotonic()
    action()
    return time.monotonic() - start


def line_minimum(program: str, points: list[str]) -> tuple[int, float]:
    items = [i.text for i in program_items(program)] + [i.text for i in point_items(points)]
    size = sum(len(t) + 1 for t in items)
    return size, size * SETTINGS.seconds_per_char


def thesis_load(
    controller: VirtualController, latency: float, items: list[str], numbers: list[str]
) -> None:
    """One thesis load operation (protocol.md §4.2 items 2, 3/4, 7) on a new connection."""
    link = paced(controller, latency)
    try:
        for command in ("OPEN=NARCUSR", "PARRLNG", "PDIRTOP", "PPOSF", "PARMEXTL", "KEYWDptest"):
            link.exchange(Request(command))
        for command in ("NEW", "LOAD=1", "PRTVERLISTL", "PRTVEREMDAT"):
            link.exchange(Request(command))
        link.exchange(Request("LISTL<", slot=9))
        for batch in (numbers, items):
            if batch:
                for chunk in chunk_emdat(batch):  # S7: ≤ 255; ours: ≤ 254, see REQUEST_LIMIT
                    link.exchange(chunk.request)
        link.exchange(Request("SAVE"))
        link.exchange(Request("CLOSE"))
    finally:
        link.close()


def thesis_init_deinit(controller: VirtualController, latency: float) -> None:
    """initRobot (§4.2 item 1) and its deinit, with the 2 s / 1 s sleeps."""
    link = paced(controller, latency)
    try:
        for command in ("OPEN=NARCUSR", "CNTLON", "RSTPRG", "PRGLOAD=1", "SRVON"):
            link.exchange(Request(command))
        time.sleep(2.0)
        link.exchange(Request("EXECBASE (0,0,0,0,0,0,0,0)"))
        link.exchange(Request("SRVOFF"))
        time.sleep(1.0)
        link.exchange(Request("CNTLOFF"))
        link.exchange(Request("CLOSE"))
    finally:
        link.close()


def fresh_controller(program: str, points: list[str]) -> VirtualController:
    """A controller already holding the program, as when re-uploading after an edit."""
    controller = VirtualController()
    with Robot(open_sim_link(controller=controller)) as robot:
        robot.load_project(program, points)
    return controller


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else "")
    parser.add_argument("--lines", type=int, default=200)
    parser.add_argument("--points", type=int, default=20)
    parser.add_argument("--latency", type=float, default=0.0, help="controller latency, s")
    parser.add_argument("--polls", type=int, default=30)
    parser.add_argument("--no-upper-bound", action="store_true", help="skip the slow row")
    args = parser.parse_args()

    program, points = make_program(args.lines, args.points)
    size, minimum = line_minimum(program, points)
    rows: list[tuple[str, float, str]] = []

    controller = fresh_controller(program, points)
    robot = Robot(paced(controller, args.latency))
    robot.connect()  # the session is open already in real use; do not time OPEN
    ours = timed(lambda: robot.load_project(program, points))
    robot.close()

    controller = fresh_controller(program, points)
    robot = Robot(paced(controller, args.latency))
    robot.connect()
    two = timed(lambda: (robot.upload_program(program), robot.upload_points(points)))
    robot.close()

    controller = fresh_controller(program, points)
    fast = Robot(paced(controller, args.latency), RobotSettings(prtver_handshakes=False))
    fast.connect()
    no_prtver = timed(lambda: fast.load_project(program, points))
    fast.close()

    controller = fresh_controller(program, points)
    piped = Robot(paced(controller, args.latency), RobotSettings(emdat_window=2))
    piped.connect()
    pipelined = timed(lambda: piped.load_project(program, points))
    piped.close()

    program_lines = [i.text for i in program_items(program)]
    point_lines = [i.text for i in point_items(points)]
    numbers = [line.split(" ", 1)[0] for line in program_lines]
    controller = fresh_controller(program, points)

    def thesis_upload() -> None:
        thesis_load(controller, args.latency, program_lines, numbers)
        thesis_load(controller, args.latency, point_lines, [])

    thesis = timed(thesis_upload)
    stored = controller.store.get("1")
    assert stored is not None and len(stored.lines) == len(program_lines)

    rows.append((f"line-rate minimum ({size} bytes)", minimum, "1.00×"))
    rows.append(("melfa load_project (1 session)", ours, f"{ours / minimum:.2f}×"))
    rows.append(("melfa, no PRTVER handshakes", no_prtver, f"{no_prtver / minimum:.2f}×"))
    rows.append(("melfa program + points (2 sessions)", two, f"{two / minimum:.2f}×"))
    rows.append(("melfa, EMDAT window 2 [GUESS]", pipelined, f"{pipelined / minimum:.2f}×"))
    rows.append(("thesis replay (§4.2, no sleeps)", thesis, f"{thesis / minimum:.2f}×"))
    if not args.no_upper_bound:
        controller = fresh_controller(program, points)

        def thesis_with_sleeps() -> None:
            thesis_init_deinit(controller, args.latency)
            thesis_load(controller, args.latency, program_lines, numbers)
            thesis_init_deinit(controller, args.latency)
            thesis_load(controller, args.latency, point_lines, [])

        upper = timed(thesis_with_sleeps)
        rows.append(("thesis + init/deinit sleeps", upper, f"{upper / minimum:.2f}×"))

    # JPOSF polling
    controller = VirtualController()
    robot = Robot(paced(controller, args.latency))
    robot.connect()
    sample = robot.channel.sent_bytes
    robot.joints()
    request_bytes = robot.channel.sent_bytes - sample
    probe = open_sim_link(controller=VirtualController())
    probe.exchange(Request("OPEN=X"))
    answer = probe.exchange(Request("JPOSF"))
    reply_bytes = len(encode_reply(answer))
    probe.close()
    elapsed = timed(lambda: [robot.joints() for _ in range(args.polls)])
    robot.close()
    our_rate = args.polls / elapsed
    bound = 1 / ((request_bytes + reply_bytes) * SETTINGS.seconds_per_char + args.latency)

    def thesis_poll() -> None:
        link = paced(VirtualController(), args.latency)
        for command in ("OPEN=NARCUSR", "JPOSF", "CLOSE"):
            link.exchange(Request(command))
        link.close()

    thesis_polls = max(3, args.polls // 5)

    def thesis_polling() -> None:
        for _ in range(thesis_polls):
            thesis_poll()

    thesis_rate = thesis_polls / timed(thesis_polling)

    print(
        f"9600 baud 8E2 ({SETTINGS.seconds_per_char * 1000:.2f} ms/char), controller latency "
        f"{args.latency:g} s; {args.lines}-line program, {args.points} points"
    )
    print()
    print(f"{'upload':40} {'seconds':>8} {'÷ line min':>11} {'thesis ÷ this':>14}")
    for name, seconds, ratio in rows:
        speedup = f"{thesis / seconds:.2f}×" if seconds else ""
        print(f"{name:40} {seconds:8.2f} {ratio:>11} {speedup:>14}")
    print()
    print(f"{'JPOSF polling':40} {'Hz':>8} {'÷ bound':>11}")
    print(f"{'line bound (+latency)':40} {bound:8.2f} {'1.00':>11}")
    print(f"{'melfa joints()':40} {our_rate:8.2f} {our_rate / bound:11.2f}")
    print(f"{'thesis (reconnect per read)':40} {thesis_rate:8.2f} {thesis_rate / bound:11.2f}")


if __name__ == "__main__":
    main()
