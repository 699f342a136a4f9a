"""Upload and polling speed on a simulated 9600-baud 8E2 line, against two yardsticks.

Run: ``.venv/bin/python bench/bench_link.py [--latencies 0,0.12] [--lines 200] [--points 20]``

Everything runs in one process on the same link: the virtual controller in memory behind
`melfa.link.PacedLink`, which delays every byte by 12 bits / 9600 baud = 1.25 ms each way
and adds a controller processing time before each reply. One run prints the whole table
twice: with **zero latency** (the wire alone) and with the **realistic 0.12 s** (prior-art.md
§5 measured 100–150 ms per reply on a CRn-5xx), so the README can quote both. Measured:

1. **Line-rate minimum**: the program and point lines, one separator each, sent once:
   ``bytes × 12 / 9600``. Nothing can upload faster over this line.
2. **melfa**: `Robot.load_project` with default settings (one session; one LOAD…SAVE holding
   program + points; the old program is deleted *inside* that edit by ``ECLR``, which clears
   steps and positions [DOC S1 §5.2; TRACE S21], so a failed upload leaves the old program
   in place). Because the thesis deletes with separate commands, a like-for-like row times
   `Robot.delete` (RSTPRG, FDEL1 in the same session) followed by `load_project`. For
   comparison: `upload_program` + `upload_points` (two LOAD…SAVE sessions), without the
   PRTVER handshakes, and with two EMDAT requests in flight (``emdat_window=2``, a [GUESS]
   about the controller's input buffering, off by default). Every melfa row re-uploads over
   a controller that already holds the program (as after an edit), the session already open.
3. **Thesis replay**, its "load project" (thesis §6.7: delete what is in slot 1, send the
   code, then the points; protocol.md §4.2, S7 ``execute_node.cpp``/``melfa.cpp``), three
   operations, each on its own new connection:
   - delete (§4.2 item 6): OPEN=NARCUSR, SAVE, CNTLON, RSTPRG, CNTLOFF, FDEL1, CLOSE;
   - program, then points (§4.2 items 2–4, 7): "connect for load" (OPEN=NARCUSR, PARRLNG,
     PDIRTOP, PPOSF, PARMEXTL, KEYWDptest), NEW, LOAD=1, PRTVERLISTL, PRTVEREMDAT,
     ``1;9;LISTL<``, EMDAT of bare line numbers (clearing; program only), EMDAT of the lines
     (S7 packs up to 255 characters), SAVE, CLOSE.
   Every reply is checked: a refusal in the replay aborts the benchmark (a refused command
   would be cheaper than a real one). What we do *not* replay, to be generous to the thesis:
   the 2 s / 1 s sleeps of its motion init/deinit (initRobot's SRVON wait and the SRVOFF
   wait are not part of the load path in §4.2), the port open/close time of a real adapter,
   and S7's off-by-one chunking slips. A further row adds initRobot/deinit around the program
   and the points operations (as §4.2 says the thesis did for every command), for an upper
   bound (``--no-upper-bound`` skips it).
4. **JPOSF polling**: back-to-back `Robot.joints()` against the line bound
   ``1 / ((request + reply bytes) × 12 / 9600)``; the thesis reconnected for each read
   (OPEN, JPOSF, CLOSE).

The aims: melfa within 1.2× of the line-rate minimum, and ≥ 2× faster than the thesis.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from dataclasses import dataclass

from melfa.lang.plan import UploadPlan, plan_upload
from melfa.link import Link, LinkSettings, PacedLink
from melfa.protocol import Ok, Request, chunk_emdat, encode_reply
from melfa.robot import Robot, RobotSettings
from melfa.sim import VirtualController, open_sim_link

SETTINGS = LinkSettings()  # 9600 8E2
REALISTIC_LATENCY_S = 0.12
"""Controller processing time per reply: prior-art.md §5 measured 100–150 ms."""


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


def project(program: str, points: list[str]) -> UploadPlan:
    """The upload plan of a program and its points (as lines)."""
    return plan_upload(program, "\n".join(points))


def line_minimum(program: str, points: list[str]) -> tuple[int, float]:
    items = [i.text for i in project(program, points).items]
    size = sum(len(t) + 1 for t in items)
    return size, size * SETTINGS.seconds_per_char


def send(link: Link, request: Request, allow: tuple[int, ...] = ()) -> None:
    """One replayed request; a refusal would make the replay cheaper than the real thing,
    so any refusal not in ``allow`` aborts the benchmark."""
    reply = link.exchange(request)
    if not isinstance(reply, Ok) and getattr(reply, "error", None) not in allow:
        raise SystemExit(f"thesis replay: {request.command[:30]!r} was refused: {reply}")


def thesis_delete(controller: VirtualController, latency: float) -> None:
    """The thesis's delete (protocol.md §4.2 item 6) on its own connection."""
    link = paced(controller, latency)
    try:
        for command in ("OPEN=NARCUSR", "SAVE", "CNTLON", "RSTPRG", "CNTLOFF", "FDEL1"):
            send(link, Request(command))
        send(link, Request("CLOSE"))
    finally:
        link.close()


def thesis_load(
    controller: VirtualController, latency: float, items: list[str], numbers: list[str]
) -> None:
    """One thesis load operation (protocol.md §4.2 items 2, 3/4, 7) on a new connection."""
    link = paced(controller, latency)
    try:
        for command in ("OPEN=NARCUSR", "PARRLNG", "PDIRTOP", "PPOSF", "PARMEXTL", "KEYWDptest"):
            send(link, Request(command))
        for command in ("NEW", "LOAD=1", "PRTVERLISTL", "PRTVEREMDAT"):
            send(link, Request(command))
        send(link, Request("LISTL<", slot=9))
        for batch in (numbers, items):
            if batch:
                for chunk in chunk_emdat(batch):  # S7: ≤ 255; ours: ≤ 254, see REQUEST_LIMIT
                    send(link, chunk.request)
        send(link, Request("SAVE"))
        send(link, Request("CLOSE"))
    finally:
        link.close()


def thesis_init_deinit(controller: VirtualController, latency: float) -> None:
    """initRobot (§4.2 item 1) and its deinit, with the 2 s / 1 s sleeps. PRGLOAD=1 (S6
    loads its own COSIROP program) may meet an empty slot after the delete: its 4140
    refusal costs the same round trip, so it is allowed."""
    link = paced(controller, latency)
    try:
        for command in ("OPEN=NARCUSR", "CNTLON", "RSTPRG"):
            send(link, Request(command))
        send(link, Request("PRGLOAD=1"), allow=(4140,))
        send(link, Request("SRVON"))
        time.sleep(2.0)
        send(link, Request("EXECBASE (0,0,0,0,0,0,0,0)"))
        send(link, Request("SRVOFF"))
        time.sleep(1.0)
        send(link, Request("CNTLOFF"))
        send(link, Request("CLOSE"))
    finally:
        link.close()


def fresh_controller(program: str, points: list[str]) -> VirtualController:
    """A controller already holding the program, as when re-uploading after an edit."""
    controller = VirtualController()
    with Robot(open_sim_link(controller=controller)) as robot:
        robot.load_project(project(program, points))
    return controller


@dataclass(frozen=True)
class Results:
    """One latency's measurements."""

    latency: float
    rows: list[tuple[str, float]]
    thesis: float
    poll_bound: float
    poll_ours: float
    poll_thesis: float


def timed_robot(
    program: str, points: list[str], latency: float, settings: RobotSettings | None = None
) -> Callable[[Callable[[Robot], object]], float]:
    """Time ``action(robot)`` on a paced link to a controller already holding the program,
    the session already open (it stays open in real use; OPEN is not timed)."""

    def run(action: Callable[[Robot], object]) -> float:
        controller = fresh_controller(program, points)
        robot = Robot(paced(controller, latency), settings)
        robot.connect()
        try:
            seconds = timed(lambda: action(robot))
        finally:
            robot.close()
        check_uploaded(controller, program, points)
        return seconds

    return run


def check_uploaded(controller: VirtualController, program: str, points: list[str]) -> None:
    """The benchmark measures complete uploads only."""
    stored = controller.store.get("1")
    plan = project(program, points)
    if stored is None or list(stored.lines.values()) != list(plan.program_texts):
        raise SystemExit("benchmark upload did not store the program")
    if len(stored.positions) != plan.point_count:
        raise SystemExit("benchmark upload did not store the points")


def measure(program: str, points: list[str], latency: float, args: argparse.Namespace) -> Results:
    """Every row of the table at one controller latency."""
    rows: list[tuple[str, float]] = []
    plan = project(program, points)
    program_only = plan_upload(program)
    points_only = plan_upload(None, "\n".join(points))
    default = timed_robot(program, points, latency)
    rows.append(("melfa load_project (ECLR deletes)", default(lambda r: r.load_project(plan))))

    def delete_then_load(robot: Robot) -> None:
        robot.delete()
        robot.load_project(plan)

    rows.append(("melfa delete() + load_project", default(delete_then_load)))
    no_prtver = timed_robot(program, points, latency, RobotSettings(prtver_handshakes=False))
    rows.append(("melfa, no PRTVER handshakes", no_prtver(lambda r: r.load_project(plan))))
    rows.append(
        (
            "melfa program + points (2 sessions)",
            default(lambda r: (r.upload_program(program_only), r.upload_points(points_only))),
        )
    )
    piped = timed_robot(program, points, latency, RobotSettings(emdat_window=2))
    rows.append(("melfa, EMDAT window 2 [GUESS]", piped(lambda r: r.load_project(plan))))

    program_lines = list(plan.program_texts)
    point_lines = list(plan.point_texts)
    numbers = [line.split(" ", 1)[0] for line in program_lines]
    controller = fresh_controller(program, points)

    def thesis_upload() -> None:
        thesis_delete(controller, latency)
        thesis_load(controller, latency, program_lines, numbers)
        thesis_load(controller, latency, point_lines, [])

    thesis = timed(thesis_upload)
    check_uploaded(controller, program, points)
    rows.append(("thesis replay: delete, program, points", thesis))
    if not args.no_upper_bound:
        controller = fresh_controller(program, points)

        def thesis_with_sleeps() -> None:
            thesis_delete(controller, latency)
            thesis_init_deinit(controller, latency)
            thesis_load(controller, latency, program_lines, numbers)
            thesis_init_deinit(controller, latency)
            thesis_load(controller, latency, point_lines, [])

        upper = timed(thesis_with_sleeps)
        check_uploaded(controller, program, points)
        rows.append(("thesis + init/deinit sleeps", upper))

    # JPOSF polling
    robot = Robot(paced(VirtualController(), latency))
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
    bound = 1 / ((request_bytes + reply_bytes) * SETTINGS.seconds_per_char + latency)

    def thesis_poll() -> None:
        link = paced(VirtualController(), latency)
        try:
            for command in ("OPEN=NARCUSR", "JPOSF", "CLOSE"):
                send(link, Request(command))
        finally:
            link.close()

    thesis_polls = max(3, args.polls // 5)

    def thesis_polling() -> None:
        for _ in range(thesis_polls):
            thesis_poll()

    thesis_rate = thesis_polls / timed(thesis_polling)
    return Results(latency, rows, thesis, bound, args.polls / elapsed, thesis_rate)


def report(results: Results, size: int, minimum: float, args: argparse.Namespace) -> None:
    print(
        f"9600 baud 8E2 ({SETTINGS.seconds_per_char * 1000:.2f} ms/char), controller latency "
        f"{results.latency:g} s per reply; {args.lines}-line program, {args.points} points"
    )
    print()
    print(f"{'upload':40} {'seconds':>8} {'÷ line min':>11} {'thesis ÷ this':>14}")
    print(f"{f'line-rate minimum ({size} bytes)':40} {minimum:8.2f} {'1.00×':>11}")
    for name, seconds in results.rows:
        speedup = f"{results.thesis / seconds:.2f}×" if seconds else ""
        print(f"{name:40} {seconds:8.2f} {seconds / minimum:10.2f}× {speedup:>14}")
    print()
    print(f"{'JPOSF polling':40} {'Hz':>8} {'÷ bound':>11}")
    print(f"{'line bound (+latency)':40} {results.poll_bound:8.2f} {'1.00':>11}")
    ours, theirs, bound = results.poll_ours, results.poll_thesis, results.poll_bound
    print(f"{'melfa joints()':40} {ours:8.2f} {ours / bound:11.2f}")
    print(f"{'thesis (reconnect per read)':40} {theirs:8.2f} {theirs / bound:11.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else "")
    parser.add_argument("--lines", type=int, default=200)
    parser.add_argument("--points", type=int, default=20)
    parser.add_argument(
        "--latencies",
        default=f"0,{REALISTIC_LATENCY_S:g}",
        help="controller latencies to measure, seconds, comma-separated",
    )
    parser.add_argument("--polls", type=int, default=30)
    parser.add_argument("--no-upper-bound", action="store_true", help="skip the slow row")
    args = parser.parse_args()
    latencies = [float(x) for x in args.latencies.split(",") if x.strip()]

    program, points = make_program(args.lines, args.points)
    size, minimum = line_minimum(program, points)
    for index, latency in enumerate(latencies):
        if index:
            print()
        report(measure(program, points, latency, args), size, minimum, args)


if __name__ == "__main__":
    main()
