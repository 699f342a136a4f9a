"""`RosCore` on a real service and virtual controller, through a recording `RosOutput`
(the binding every ROS client library implements)."""

from __future__ import annotations

import asyncio
import logging
from pathlib import Path

from melfa.ros.core import RosCore
from melfa.ros.messages import JointStateData, PoseData
from melfa.service import RobotService, ServiceConfig
from melfa.sim import VirtualController
from tests.service.helpers import ANN, RecordingController, make_service, run, until

PROGRAM = "10 SERVO ON\n20 END\n"


class Recorder:
    """A `RosOutput` and `ParamSource` keeping everything."""

    def __init__(self, params: dict[str, object] | None = None) -> None:
        self.params = params or {}
        self.joints: list[JointStateData] = []
        self.poses: list[PoseData] = []
        self.texts: list[tuple[str, str]] = []
        self.logs: list[tuple[int, str]] = []

    def joint_states(self, message: JointStateData) -> None:
        self.joints.append(message)

    def tool_pose_stamped(self, message: PoseData) -> None:
        self.poses.append(message)

    def text(self, topic: str, text: str) -> None:
        self.texts.append((topic, text))

    def log(self, level: int, text: str) -> None:
        self.logs.append((level, text))

    def get(self, name: str) -> object | None:
        return self.params.get(name)

    def on(self, topic: str) -> list[str]:
        return [text for t, text in self.texts if t == topic]


def test_instructions_are_handled_in_order_and_errors_published() -> None:
    controller = RecordingController()
    out = Recorder()

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            core = RosCore(service, ANN, out, out)
            core.start(stream=False)
            for text in [
                "---LOAD PROGRAM BEGIN---",
                *PROGRAM.splitlines(),
                "---LOAD PROGRAM END---",
            ]:
                await core.put_instruction(text)
            await core.put_instruction("---RUN PROGRAM---")
            await core.put_instruction("20 END")  # nothing announced: an error
            await core.put_instruction("---REQUEST JOINT STATE---")
            assert await until(lambda: core.instructions == 7 and bool(out.on("joint_state")))
            await core.close()

    run(main())
    commands = controller.commands(skip_polls=True)
    emdat = [i for i, c in enumerate(commands) if "EMDAT" in c]
    runs = [i for i, c in enumerate(commands) if ";RUN" in c]
    assert emdat and runs and max(emdat) < min(runs)  # the upload finished before RUN
    assert (
        len(out.on("execute_error")) == 1 and "not a control message" in out.on("execute_error")[0]
    )
    assert out.logs[0][0] == logging.INFO  # the client's mistake, not the server's error
    assert out.on("joint_state") == ["(0,0,1.5708,0,1.5708,0)"]


def test_services_read_parameters_or_files_and_report_refusals(tmp_path: Path) -> None:
    points = tmp_path / "p.pos"
    points.write_text("DEF POS P1=(400.00,0.00,600.00,180.00,0.00,180.00)(7,0)\n")
    out = Recorder({"program": PROGRAM, "points_file": str(points)})

    async def main() -> None:
        service, _ = make_service(VirtualController(), polling=False)
        async with service:
            core = RosCore(service, ANN, out, out)
            loaded = await core.call("load_project")
            assert loaded.success and loaded.message.startswith("program and points loaded")
            assert (await core.call("servo", True)).message == "servo on"
            assert (await core.call("run")).success
            out.params.clear()
            missing = await core.call("load_points")
            assert not missing.success and "~points" in missing.message
            out.params["program"] = 42
            wrong = await core.call("load_program")
            assert not wrong.success and "must be a string" in wrong.message
            unknown = await core.call("fly")
            assert not unknown.success and "load_program" in unknown.message

    run(main())


def test_the_stream_publishes_snapshots_at_most_at_the_cap() -> None:
    out = Recorder()
    ticks = [0.0]

    async def main() -> None:
        service = RobotService.from_spec("sim", config=ServiceConfig(poll_floor_s=0.01))
        async with service:
            core = RosCore(service, ANN, out, out, max_rate_hz=10, clock=lambda: ticks[0])
            core.start()
            assert await until(lambda: len(out.joints) >= 1)
            await asyncio.sleep(0.3)  # many snapshots, no time passes on the core's clock
            assert len(out.joints) == 1
            ticks[0] = 0.2
            assert await until(lambda: len(out.joints) == 2)
            await core.close()

    run(main())
    assert len(out.on("joint_state")) == len(out.joints) == 2
    assert 1 <= len(out.poses) <= 2  # the pose is known from the first PPOSF on
