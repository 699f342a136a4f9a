"""melfa: program and drive a Mitsubishi RV-6S (CR2B-574 controller, MELFA BASIC IV).

The package is layered; dependencies point one way (see docs/ARCHITECTURE.md):

    lang, kin, protocol      pure logic, no I/O
    link                     byte transports (serial, TCP, pty)
    robot                    one session with one controller
    sim                      the virtual CR2B-574
    cli                      the `melfa` command
"""

__version__ = "0.1.0"
