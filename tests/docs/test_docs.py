"""The docs are kept true by a machine: every command is in the README, every API route in
docs/api.md, every benchmark in the README's table."""

from __future__ import annotations

from pathlib import Path

import typer.main

from melfa.cli import app

ROOT = Path(__file__).resolve().parents[2]


def test_every_command_is_in_the_readme() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    commands = typer.main.get_command(app).commands  # type: ignore[attr-defined]
    missing = [name for name in commands if f"melfa {name}" not in readme]
    assert not missing, f"README.md does not mention: {missing}"


def test_every_api_route_is_in_the_api_docs() -> None:
    from melfa.web import WebSettings, create_app

    api = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    spec = create_app(WebSettings()).openapi()
    paths = {path for path in spec["paths"] if path.startswith("/api")} | {"/api/ws"}
    assert len(paths) > 20  # the app really has its routes
    missing = sorted(path for path in paths if path not in api)
    assert not missing, f"docs/api.md does not mention: {missing}"


def test_every_benchmark_is_in_the_readme_table() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    missing = [p.name for p in sorted((ROOT / "bench").glob("bench_*.py")) if p.name not in readme]
    assert not missing, f"README.md's benchmark table lacks: {missing}"


def test_the_ros_page_says_what_is_not_offered_and_why() -> None:
    ros = (ROOT / "docs" / "ros.md").read_text(encoding="utf-8")
    section = ros.split("## Not offered", 1)[1].split("\n## ", 1)[0]
    for missing in ("No `FollowJointTrajectory` action", "no MoveIt", "No ROS 2 node"):
        assert missing in section, missing
    assert "9600 baud" in section  # and why: the link, not a choice
