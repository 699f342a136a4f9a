"""Session and rights: OPEN/CLOSE, CNTLON/CNTLOFF, KEYWD, the PRTVER handshake, parameters.

[DOC S1 §3.1] OPEN must come first (6010 before it); the client name is arbitrary. The
operation rights (CNTLON) are what the `rights=True` commands of the table need (6020).
"""

from __future__ import annotations

from melfa.protocol.messages import Ok, Refused, Reply, Request
from melfa.sim import errors as err
from melfa.sim.core import Command, ControllerCore


def open_(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    c.is_open = True
    c.client = arg
    return Ok(c.config.banner.body())


def close(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    c.is_open = False
    c.rights = False
    return Ok()


def cntlon(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    c.rights = True
    return Ok()


def cntloff(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    c.rights = False
    return Ok()


def keywd(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    # [TRACE K9b-C4] `KEYWDp991231` -> `QoK`: a maintenance password; any is accepted.
    return Ok()


def prtver(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    # [TRACE K9b-READ] PRTVERVALS -> QoK1; [GUESS] the same for LISTL/EMDAT.
    return Ok(c.config.prtver_answer)


def par(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    name = arg.strip().upper()
    value = parameters(c).get(name)
    if value is None:
        return Refused(err.PARAMETER_NOT_FOUND)
    values, count = value
    return Ok(f"{name};{values};{count}")


def parameters(c: ControllerCore) -> dict[str, tuple[str, int]]:
    """Read-only parameters PAR<name> answers [TRACE S10; DERIVED for MEJAR]."""
    limits = c.arm.joint_limits
    mejar = [f"{v:.2f}" for pair in limits for v in pair]
    mejar += ["0.00"] * (16 - len(mejar))
    return {
        "RLNG": ("1", 1),
        "MEXTL": (", ".join(f"{v:.2f}" for v in c.arm.tool_values), 6),
        "MEJAR": (", ".join(mejar), 16),
        "CBAU232": ("9600", 1),
        "CPRTY232": ("2", 1),
        "CSTOP232": ("2", 1),
        "CTERM232": ("0", 1),
        "CPRC232": ("0", 1),
        "TASKMAX": (str(c.config.banner.taskmax), 1),
    }


COMMANDS = (
    Command("OPEN=", open_, needs_open=False),
    Command("CLOSE", close, exact=True),
    Command("CNTLON", cntlon, exact=True),
    Command("CNTLOFF", cntloff, exact=True),
    Command("KEYWD", keywd),
    Command("PRTVER", prtver),
    Command("PAR", par),
)
