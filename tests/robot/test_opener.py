"""Every --robot form opens through `open_robot_link`; `melfa.link` alone knows no `sim`."""

from __future__ import annotations

import pytest

from melfa.link import LinkError, MemoryLink, TraceLink, open_link
from melfa.robot import Robot, open_robot_link


def test_sim_is_an_in_process_virtual_controller() -> None:
    link = open_robot_link("sim")
    assert isinstance(link, MemoryLink)
    with Robot(link) as robot:
        banner = robot.connect()
        assert banner.program_extension == "MB4"  # a CRn-5xx, as the CR2B-574 reports


def test_sim_can_be_traced() -> None:
    lines: list[str] = []
    link = open_robot_link("sim", trace=True, trace_sink=lines.append)
    assert isinstance(link, TraceLink)
    with Robot(link) as robot:
        robot.connect()
    assert any("OPEN=" in line for line in lines)


def test_the_link_layer_refuses_sim_with_a_pointer() -> None:
    with pytest.raises(LinkError, match="open_robot_link"):
        open_link("sim")


def test_other_forms_go_to_the_link_layer() -> None:
    with open_robot_link("loop://") as link:
        assert not isinstance(link, MemoryLink)
