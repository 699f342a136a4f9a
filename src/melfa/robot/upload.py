"""What the robot needs of an upload plan: that it can be sent.

The plan itself (lines to send, step → line map, diagnostics, the gate's fingerprint) is
`melfa.lang.plan.plan_upload`, made once by whoever loads (CLI, web, ROS, the thesis's
messages) and handed down. The robot sends a plan's items as they are; a plan that cannot be
sent at all (a non-ASCII character in code, a program that cannot be numbered, broken points)
is refused here with where, before anything goes out. Checker errors do not stop the robot:
check-before-upload is the caller's policy (the service's, or ``melfa upload`` without
``--force``).

>>> from melfa.lang.plan import plan_upload
>>> try:
...     sendable(plan_upload("MOV Pé\\n"))
... except UploadPreparationError as exc:
...     print(exc.source, exc.line, exc.column)
program 1 6
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from melfa.robot.errors import RobotError

if TYPE_CHECKING:
    from melfa.lang.plan import UploadPlan


class UploadPreparationError(RobotError):
    """Program or points that cannot be sent as they are; ``source`` (program or points),
    ``line`` and ``column`` say where (1-based)."""

    def __init__(self, message: str, *, source: str, line: int, column: int = 1) -> None:
        super().__init__(f"{source} line {line}: {message}")
        self.source = source
        self.line = line
        self.column = column
        self.reason = message


def sendable(plan: UploadPlan) -> UploadPlan:
    """``plan`` itself, or `UploadPreparationError` naming why it cannot be sent."""
    blocker = plan.blocker
    if blocker is None:
        return plan
    found = blocker.diagnostic
    message = found.message
    if found.rule.startswith("numbering"):
        message = f"cannot number the program: {message}"
    raise UploadPreparationError(
        message, source=blocker.source.value, line=found.line, column=found.column
    )


__all__ = ["UploadPreparationError", "sendable"]
