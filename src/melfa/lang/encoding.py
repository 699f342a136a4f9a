"""How program and points files are read, everywhere (IDE imports, the ROS node's
``~program_file``): Windows tools write UTF-8 or Windows-1252 with CRLF line ends."""

from __future__ import annotations


def decode_text(data: bytes | str) -> str:
    """Text of a program or points file: UTF-8 (BOM allowed), else Windows-1252; LF line
    ends.

    >>> decode_text(b"10 MOV P1\\r\\n20 END\\r\\n"), decode_text("caf\\xe9".encode("cp1252"))
    ('10 MOV P1\\n20 END\\n', 'café')
    """
    if isinstance(data, bytes):
        try:
            text = data.decode("utf-8-sig")
        except UnicodeDecodeError:
            text = data.decode("cp1252", errors="replace")
    else:
        text = data.removeprefix("\ufeff")
    return text.replace("\r\n", "\n").replace("\r", "\n")


__all__ = ["decode_text"]
