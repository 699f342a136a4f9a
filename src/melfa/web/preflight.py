"""The lab's pre-flight wiring: its cell model (a JSON file in the data directory, edited by
instructors; each edit audited here, its one place). The check itself is
`melfa.sim.debug.preflight`; the instructor's gate that a pass opens
(`WebSettings.require_simulation`) is the lab service's policy
(`melfa.service.policy.Gate`), which every door passes, not only the web's. The gate reads
the cell's version here (`Preflight.version`): a pass in an earlier cell no longer counts."""

from __future__ import annotations

import json
import logging
import threading
from pathlib import Path

from melfa.sim.debug.cell import Cell, CellError
from melfa.store import AuditEvent, User
from melfa.store.audit import AuditLog
from melfa.vocab.desk import DeskAction

CELL_FILE = "cell.json"
_log = logging.getLogger("melfa.web.preflight")


class Preflight:
    """The cell (kept in ``data_dir/cell.json``); every edit recorded in ``audit``."""

    def __init__(self, data_dir: Path, audit: AuditLog | None = None) -> None:
        self.path = data_dir / CELL_FILE
        self.audit = audit
        self._lock = threading.Lock()
        self.cell = self._read()
        self.version = self.cell.digest()
        """`Cell.digest` of the cell as it is now: the instructor's gate counts a pre-flight
        only in this version (`melfa.service.policy.Gate.cell` reads it)."""

    def _read(self) -> Cell:
        try:
            return Cell.from_json(self.path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            return Cell()
        except (OSError, CellError) as exc:
            _log.warning("cell model %s unusable (%s): the default is used", self.path, exc)
            return Cell()

    def save_cell(self, cell: Cell, by: User | None = None) -> None:
        """Keep ``cell`` (replacing the file at once) and audit who edited it."""
        with self._lock:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            tmp = self.path.with_suffix(".tmp")
            tmp.write_text(json.dumps(cell.to_json(), indent=2) + "\n", encoding="utf-8")
            tmp.replace(self.path)
            self.cell, self.version = cell, cell.digest()
        if self.audit is not None:
            self.audit.record(
                AuditEvent(
                    action=DeskAction.CELL.value,
                    actor=None if by is None else by.username,
                    role=None if by is None else by.role.value,
                    details={
                        "obstacles": len(cell.obstacles),
                        "parts": len(cell.parts),
                        "sensors": len(cell.sensors),
                    },
                )
            )


__all__ = ["CELL_FILE", "Preflight"]
