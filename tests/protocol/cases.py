"""One table of (typed message, exact bytes) for the writer and reader tests."""

from melfa.protocol import EditRefused, Ok, Refused, Reply, Request

REQUESTS: list[tuple[Request, bytes]] = [
    (Request("OPEN=NARCUSR"), b"1;1;OPEN=NARCUSR\r"),
    (Request("CNTLON"), b"1;1;CNTLON\r"),
    (Request("RUN1;1"), b"1;1;RUN1;1\r"),
    (Request("STOP", slot=0), b"1;0;STOP\r"),
    (Request("EMDAT10 MOV P1\x0b20 MOV P2", slot=9), b"1;9;EMDAT10 MOV P1\x0b20 MOV P2\r"),
    (Request("EXECMOV P_CURR*(0,0,5,0,0,0)"), b"1;1;EXECMOV P_CURR*(0,0,5,0,0,0)\r"),
    (Request("JOG01;00;00;01;00"), b"1;1;JOG01;00;00;01;00\r"),
    (Request("HOTMoveit.MB4;M1=0", robot=2, slot=33), b"2;33;HOTMoveit.MB4;M1=0\r"),
]

# Replies quoted in protocol.md, plus one of each form.
REPLIES: list[tuple[Reply, bytes]] = [
    (Ok(), b"QoK\r"),
    (Ok("50"), b"QoK50\r"),
    (Ok("4140;2", alarm=True), b"Qok4140;2\r"),
    (Ok("The program was not found"), b"QoKThe program was not found\r"),
    (
        Ok("2.MB5;100;100;5;A1124220;1;1;;;;;;;;;REP;START;1;0", alarm=True),
        b"Qok2.MB5;100;100;5;A1124220;1;1;;;;;;;;;REP;START;1;0\r",
    ),
    (Ok("09060;17;1"), b"QoK09060;17;1\r"),
    (Refused(6020), b"QeR6020\r"),
    (Refused(5640, alarm=True), b"Qer5640\r"),
    (EditRefused(4220, 2, 5, alarm=True), b"Qer4220;2;5\r"),
    (EditRefused(4220, 3, 1, alarm=False), b"QeR4220;3;1\r"),
    (EditRefused(4220, None, 7, alarm=True), b"Qer4220;7\r"),
]
