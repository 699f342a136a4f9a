"""The virtual CR2B-574: answers the R-protocol like the real controller, without the robot.

- `VirtualController`: the sans-I/O core, one request line in, one reply out, time injected.
- `open_sim_link()`: an in-process `melfa.link.Link` to it (`--robot sim`).
- `PtyServer` / `TcpServer`: serve it on a fresh pseudo-terminal per connection (pyserial
  opens the slave at 9600 8E2, the real serial code path) or on `tcp://host:port`.
- `SimConfig`: every [GUESS] of protocol.md that changes what a client sees, and the real
  controller's situations: the MODE key (`KeySwitch`), a lost origin, 4- or 9-digit
  refusals, strict mode (docs/simulator.md).
- `ProgramRunner` / `StatementExecutor`: the hooks the interpreter (`melfa.sim.interp`) fills.

I/O signals: one `IOState` per controller (`VirtualController.io`), shared by RUN and EXEC;
`set_input` drives inputs from outside, `IN`/`OUT` read them over the protocol.

What it does not do: parameters beyond the few read-only ones on record, variables through VAL/HOT,
file transfer (FOPEN…), procedural mode, more than one mechanism.
"""

from melfa.sim.config import KeySwitch, SimConfig
from melfa.sim.controller import SUPPORTED_COMMANDS, VirtualController
from melfa.sim.memory import open_sim_link
from melfa.sim.runner import ProgramRunner, RunnerStatus, StatementExecutor, StepError
from melfa.sim.servers import PtyServer, TcpServer
from melfa.sim.session import NO_PACING, Pacing, WireSession

__all__ = [
    "NO_PACING",
    "SUPPORTED_COMMANDS",
    "KeySwitch",
    "Pacing",
    "ProgramRunner",
    "PtyServer",
    "RunnerStatus",
    "SimConfig",
    "StatementExecutor",
    "StepError",
    "TcpServer",
    "VirtualController",
    "WireSession",
    "open_sim_link",
]
