"""Session and rights: OPEN/CLOSE, CNTLON/CNTLOFF, KEYWD, the PRTVER handshake, parameters.

[DOC S1 §3.1] OPEN must come first (6010 before it) where `open_required` says so; real
clients that never sent it were answered. The client name is arbitrary. The
operation rights (CNTLON) are what the `rights=True` commands of the table need (6020).
"""

from __future__ import annotations

from melfa.protocol.listings import Parameter
from melfa.protocol.messages import Ok, Refused, Reply, Request
from melfa.sim import errors as err
from melfa.sim.core import ControllerCore, Handler


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
    """`PAR<name>` and `PNR<name>`: `<name>;<values>;<count>` [TRACE K4a-CR2B, K9b-C4]."""
    name = arg.strip().upper()
    values = parameters(c).get(name)
    if values is None:
        return Refused(err.PARAMETER_NOT_FOUND)
    return Ok(Parameter(name, values, len(values)).to_answer())


def parameters(c: ControllerCore) -> dict[str, tuple[str, ...]]:
    """The read-only parameters the simulator answers: the recorded ones with the values a
    real controller showed [TRACE K4a-CR2B, K9b-C4], limits and tool from the arm, and the
    serial settings the simulator itself uses."""
    limits = c.arm.joint_limits
    mejar = [f"{v:.2f}" for pair in limits for v in pair]
    mejar += ["0.00"] * (16 - len(mejar))
    return {
        "RLNG": ("1",),
        "LNG": (c.config.banner.language,),
        "MEXTL": tuple(f"{v:.2f}" for v in c.arm.tool_values),
        "MEJAR": tuple(mejar),
        "RMTPSL": ("0",),
        "OVRDMD": ("0", "0"),
        "JOGJSP": ("0.10", "0.01", "10.00"),
        "SRVON": ("4", "1"),
        "CBAU232": ("9600",),
        "CPRTY232": ("2",),
        "CSTOP232": ("2",),
        "CTERM232": (c.config.cterm.value,),
        "CPRC232": ("0",),
        "TASKMAX": (str(c.config.banner.taskmax),),
    }


HANDLERS: dict[str, Handler] = {
    "OPEN=": open_,
    "CLOSE": close,
    "CNTLON": cntlon,
    "CNTLOFF": cntloff,
    "KEYWD": keywd,
    "PRTVER": prtver,
    "PAR": par,
    "PNR": par,
}
