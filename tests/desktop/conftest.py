"""A real `melfa serve` (virtual robot) in a subprocess on a free port, shared by the
desktop tests; Qt fixtures live in the Qt test modules so the pure ones run without it."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.serving import melfa_serve

ADMIN_PASSWORD = "desktop-test-pass-1"
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@dataclass(frozen=True)
class Server:
    url: str
    password: str


@pytest.fixture(scope="package")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    data = tmp_path_factory.mktemp("desktop-data")
    with melfa_serve(data, admin_password=ADMIN_PASSWORD, timeout=60) as url:
        yield Server(url, ADMIN_PASSWORD)
