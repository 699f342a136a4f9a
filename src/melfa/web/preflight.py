"""The lab's pre-flight wiring: its cell model (a JSON file in the data directory, edited by
instructors) and the instructor's gate (`WebSettings.require_simulation`): the lab robot
loads and runs a program only after the same text passed a simulated run without
pre-flight errors. The check itself is `melfa.sim.debug.preflight`."""

from __future__ import annotations

import json
import logging
import threading
from pathlib import Path

from melfa.sim.debug.cell import Cell, CellError

CELL_FILE = "cell.json"
_log = logging.getLogger("melfa.web.preflight")


class Preflight:
    """The cell (kept in ``data_dir/cell.json``) and the texts that passed pre-flight."""

    def __init__(self, data_dir: Path, *, require_simulation: bool = False) -> None:
        self.path = data_dir / CELL_FILE
        self.require_simulation = require_simulation
        self._lock = threading.Lock()
        self._passed: set[str] = set()
        self.lab_loaded: str | None = None
        """Fingerprint of what was last loaded into the lab robot through the gate."""
        self.cell = self._read()

    def _read(self) -> Cell:
        try:
            return Cell.from_json(self.path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            return Cell()
        except (OSError, CellError) as exc:
            _log.warning("cell model %s unusable (%s): the default is used", self.path, exc)
            return Cell()

    def save_cell(self, cell: Cell) -> None:
        with self._lock:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            tmp = self.path.with_suffix(".tmp")
            tmp.write_text(json.dumps(cell.to_json(), indent=2) + "\n", encoding="utf-8")
            tmp.replace(self.path)
            self.cell = cell

    def passed(self, fingerprint: str) -> None:
        """A plan's fingerprint (`melfa.lang.plan.UploadPlan.fingerprint`) passed."""
        with self._lock:
            self._passed.add(fingerprint)

    def has_passed(self, fingerprint: str) -> bool:
        with self._lock:
            return fingerprint in self._passed


__all__ = ["CELL_FILE", "Preflight"]
