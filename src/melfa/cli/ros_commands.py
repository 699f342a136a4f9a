"""`melfa ros`: the robot as a ROS 1 node (topics, services; see docs/ros.md).

rospy comes from Debian's ROS Noetic packages and imports only under ``/usr/bin/python3``.
Run from the project's ``.venv``, the command re-executes itself in ``.venv-ros`` when
``scripts/ros-env`` has set that up, and otherwise says how to run it — never a traceback.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape

import melfa
from melfa.cli.typer_app import app
from melfa.link import RobotSpecError, parse_robot

REEXEC_ENV = "MELFA_ROS_REEXEC"
"""Set when `melfa ros` re-executed itself under the ROS environment (no second try)."""

_err = Console(stderr=True, highlight=False, soft_wrap=True, emoji=False)


def ros_python() -> Path | None:
    """``.venv-ros/bin/python`` of this checkout, if `scripts/ros-env` has made it."""
    root = Path(melfa.__file__).resolve().parents[2]
    candidate = root / ".venv-ros" / "bin" / "python"
    return candidate if candidate.exists() else None


def _fail(message: str, code: int) -> typer.Exit:
    _err.print(f"[bold red]error:[/] {escape(message)}")
    return typer.Exit(code)


@app.command("ros")
def ros(
    remap: Annotated[
        list[str] | None,
        typer.Argument(
            metavar="[REMAP]...",
            help="ROS remappings and special arguments: joint_states:=/arm/joint_states, "
            "__ns:=arm, _max_rate:=20.",
            show_default=False,
        ),
    ] = None,
    robot_option: Annotated[
        str | None,
        typer.Option(
            "--robot",
            "-r",
            metavar="ROBOT",
            help="Serial device, tcp://host:port, a pyserial URL, or 'sim' (the in-process "
            "virtual controller). Default: $MELFA_ROBOT, else sim.",
            show_default=False,
        ),
    ] = None,
    name: Annotated[
        str, typer.Option("--name", help="Node name; services live under /NAME/.")
    ] = "melfa",
    max_rate: Annotated[
        float | None,
        typer.Option(
            "--max-rate",
            metavar="HZ",
            help="Publish state at most this often (default: every state the robot reports).",
            show_default=False,
        ),
    ] = None,
    frame_id: Annotated[
        str, typer.Option("--frame-id", help="frame_id of tool_pose_stamped.")
    ] = "base",
    mode: Annotated[
        str,
        typer.Option(
            "--mode",
            help="melfa, or thesis: behave exactly like the thesis's execute node (answers "
            "without parentheses and only when asked, 20 mm base-frame jog, servo on at "
            "start); also the parameter ~mode.",
        ),
    ] = "melfa",
    description: Annotated[
        bool,
        typer.Option(
            "--description/--no-description",
            help="Set /robot_description to the RV-6S URDF (for robot_state_publisher).",
        ),
    ] = True,
    print_urdf: Annotated[
        bool,
        typer.Option(
            "--print-urdf", help="Print the RV-6S URDF (from melfa.kin's DH table) and exit."
        ),
    ] = False,
) -> None:
    """Run the robot as a ROS 1 node: /execute_instruction in (the thesis's control
    messages); /joint_states, /tool_pose_stamped, /tool_pose, /joint_state, /execute_error
    out; services /NAME/load_program, load_points, load_project, run, stop, delete, servo,
    reset, override, state; /robot_description set to the RV-6S URDF."""
    if print_urdf:
        from melfa.ros.urdf import rv6s_urdf

        sys.stdout.write(rv6s_urdf())
        return
    if max_rate is not None and max_rate <= 0:
        raise _fail(f"--max-rate must be positive, not {max_rate}", 2)
    from melfa.service.thesis import dialect_named

    try:
        dialect_named(mode)
    except ValueError as exc:
        raise _fail(f"--mode: {exc}", 2) from None
    try:
        robot = parse_robot(robot_option).text
    except RobotSpecError as exc:
        raise _fail(str(exc), 2) from None
    from melfa.ros.node import ros_available

    args = list(remap or [])
    if not ros_available():
        python = ros_python()
        if python is not None and not os.environ.get(REEXEC_ENV):
            argv = [str(python), "-m", "melfa", "ros", *args, "--robot", robot, "--name", name]
            argv += ["--frame-id", frame_id, "--mode", mode]
            if not description:
                argv.append("--no-description")
            if max_rate is not None:
                argv += ["--max-rate", str(max_rate)]
            os.environ[REEXEC_ENV] = "1"
            sys.stdout.flush()
            sys.stderr.flush()
            os.execv(str(python), argv)
        raise _fail(
            f"rospy does not import in this Python ({sys.executable}). ROS 1 Noetic's rospy "
            "is Debian's and lives in /usr/bin/python3: run `scripts/ros-env melfa ros "
            f"--robot {robot}` from the melfa checkout (it sets up .venv-ros the first time).",
            2,
        )
    import importlib

    rosgraph = importlib.import_module("rosgraph")
    uri = rosgraph.get_master_uri()
    if not rosgraph.Master(f"/{name}", master_uri=uri).is_online():
        raise _fail(f"no ROS master answers at {uri}: start `roscore` first", 3)

    from melfa.ros.node import run_node

    run_node(
        robot,
        node_name=name,
        max_rate_hz=max_rate,
        frame_id=frame_id,
        mode=mode,
        description=description,
        argv=args,
    )
