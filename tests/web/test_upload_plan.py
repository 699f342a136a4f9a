"""A load through the web API plans the upload once: one tokenization of the program, and
the step → line map the IDE gets is the numbering that was sent."""

from __future__ import annotations

import sys
import threading
import types
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from melfa.lang import lexer
from melfa.store import Store
from melfa.web import WebSettings, create_app
from tests.waiting import wait_until
from tests.web.conftest import TestClient, Web, fast_service

POINTS = "DEF POS P1=(300.00,0.00,450.00,180.00,0.00,180.00)(7,0)\n"
LOOP = "1 MOV P1\n2 GOTO 1\n3END"


class Tokenizations:
    """Records calls of `melfa.lang.lexer.tokenize` in every thread (the request's, the CPU
    pool's, the service worker's), leaving out the virtual controller's own reading of what
    it was sent: a profile hook, set before the app's threads start."""

    def __init__(self) -> None:
        self.counting = False
        self.texts: list[str] = []
        """The text of each call."""

    def hook(self, frame: types.FrameType, event: str, arg: Any) -> None:
        if event != "call" or not self.counting or frame.f_code is not lexer.tokenize.__code__:
            return
        caller: types.FrameType | None = frame.f_back
        while caller is not None:
            if "/melfa/sim/" in caller.f_code.co_filename:
                return  # the controller parsing the lines it received
            caller = caller.f_back
        self.texts.append(str(frame.f_locals["text"]))


@pytest.fixture
def counted(store: Store, tmp_path: Path) -> Iterator[tuple[Web, Tokenizations]]:
    counter = Tokenizations()
    threading.setprofile(counter.hook)
    sys.setprofile(counter.hook)
    try:
        settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service())
        app = create_app(settings, store=store)
        with TestClient(app) as client:
            yield Web(client, store, app), counter
    finally:
        sys.setprofile(None)
        threading.setprofile(None)  # type: ignore[arg-type]


def test_a_load_tokenizes_the_program_once(counted: tuple[Web, Tokenizations]) -> None:
    web, counter = counted
    ann = web.ann
    program = "SERVO ON\nMOV P1\nEND\n"
    counter.counting = True
    response = ann.post("/api/robot/project", json={"program": program, "points": POINTS})
    counter.counting = False
    assert response.status_code == 200, response.text
    assert counter.texts.count(program) == 1
    assert len(counter.texts) == len(set(counter.texts)), counter.texts  # nothing twice


def test_a_program_numbered_by_its_tokens_shows_its_running_line(web: Web) -> None:
    ann = web.ann
    report = ann.post("/api/robot/project", json={"program": LOOP, "points": POINTS}).json()
    assert report["step_lines"] == {"1": 1, "2": 2, "3": 3}
    assert ann.post("/api/robot/run", json={"servo_on": True}).status_code == 200

    def running_line() -> bool:
        state = ann.get("/api/robot/state").json()
        return state["running"] and str(state["line"]) in report["step_lines"]

    wait_until(running_line)  # the controller reports steps 1 and 2, never 10 or 20
    ann.post("/api/robot/stop")
