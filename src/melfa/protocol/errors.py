"""Whose fault is it: our misuse, or a garbled peer.

A controller *refusal* (`QeR…`) is neither: it is data (`melfa.protocol.Refused`), and the
robot client turns it into `melfa.robot.ControllerError`.
"""

from __future__ import annotations


class ProtocolError(Exception):
    """Base of the two protocol failures below."""


class LocalProtocolError(ProtocolError):
    """We asked for something the protocol cannot carry (too long, bad character, wrong turn)."""


class RemoteProtocolError(ProtocolError):
    """The peer sent bytes that are not a valid message (garbled, unknown, never terminated).

    `error_number` is set when the real controller would answer the offending *request* with a
    known error, so the virtual controller can reply the same way (e.g. 6080 for an over-long
    command, 6010 for an illegal one).
    """

    def __init__(self, message: str, *, error_number: int | None = None) -> None:
        super().__init__(message)
        self.error_number = error_number
