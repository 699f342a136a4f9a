import pytest

from melfa.protocol import Jog, JogInch, JogMode, LocalProtocolError, RemoteProtocolError


@pytest.mark.parametrize(
    ("jog", "text"),
    [
        (Jog.axis(JogMode.XYZ, 0, +1), "JOG01;00;00;01;00"),  # S17 C# "plus"
        (Jog.axis(JogMode.XYZ, 0, -1), "JOG01;00;01;00;00"),  # S17 C# "minus": − before +
        (Jog.axis(JogMode.JOINT, 6, +1), "JOG00;00;00;40;00"),  # S17 Python (J7)
        (Jog.axis(JogMode.TOOL, 2, -1, JogInch.LOW), "JOG02;00;04;00;02"),
        (Jog(JogMode.CYLINDRICAL, negative=0x80, positive=0x01), "JOG05;00;80;01;00"),
        (Jog(JogMode.XYZ3), "JOG04;00;00;00;00"),
    ],
)
def test_jog_text_and_back(jog: Jog, text: str) -> None:
    assert jog.command == text
    assert Jog.parse(text) == jog


def test_jog_misuse() -> None:
    with pytest.raises(LocalProtocolError, match="both directions"):
        Jog(JogMode.XYZ, negative=1, positive=3)
    with pytest.raises(LocalProtocolError, match="axis 8"):
        Jog.axis(JogMode.XYZ, 8, 1)
    with pytest.raises(LocalProtocolError, match="direction 0"):
        Jog.axis(JogMode.XYZ, 0, 0)


@pytest.mark.parametrize(
    "text", ["JOG01;00;01;00;00;00", "JOG03;00;00;01;00", "JOG01;00;01;01;00", "JOG1;0;0;1;0"]
)
def test_jog_parse_refuses(text: str) -> None:
    with pytest.raises(RemoteProtocolError) as exc:
        Jog.parse(text)
    assert exc.value.error_number == 6010
