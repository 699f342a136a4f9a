"""How program and points files are decoded, everywhere: the one reading of their bytes.

Every command and door that takes a program reads its bytes through `decode_file` (the
CLI's `melfa.cli.checking.read_source` for check, fmt, upload, debug and sim --run; IDE
imports, the desktop client and the ROS node's ``~program_file`` through `decode_text`):

* UTF-16 with a BOM (Windows Notepad), then UTF-8 (a BOM is dropped), then Windows-1252,
  then Latin-1, which never fails, so an accented comment never stops a file being read
  and writing it back in the same encoding gives the same bytes;
* a NUL byte outside UTF-16 means the file is not text (a binary export, the controller's
  own ``ROBPRG`` program files): `Decoded.binary_at` says where, and callers refuse it.
"""

from __future__ import annotations

import codecs
from typing import NamedTuple


class Decoded(NamedTuple):
    """A file's text, how it was encoded, and where a NUL byte shows it is not text."""

    text: str
    encoding: str
    bom: bytes
    binary_at: tuple[int, int] | None = None  # (line, column) of the first NUL byte


_UTF16 = ((codecs.BOM_UTF16_LE, "utf-16-le"), (codecs.BOM_UTF16_BE, "utf-16-be"))


def decode_file(raw: bytes) -> Decoded:
    """The text of a program or points file's bytes (line ends as written).

    >>> decode_file("10 MOV P1\\n".encode("utf-16")).text
    '10 MOV P1\\n'
    >>> decode_file(b"ROBPRG\\x00\\x00").binary_at
    (1, 7)
    """
    for bom, encoding in _UTF16:
        if raw.startswith(bom):
            try:
                return Decoded(raw[len(bom) :].decode(encoding), encoding, bom)
            except UnicodeDecodeError:
                break
    nul = raw.find(b"\x00")
    if nul >= 0:
        before = raw[:nul].decode("latin-1")
        line = before.count("\n") + 1
        column = nul - (before.rfind("\n") + 1) + 1
        return Decoded("", "latin-1", b"", (line, column))
    bom = b""
    if raw.startswith(codecs.BOM_UTF8):
        bom, raw = codecs.BOM_UTF8, raw[len(codecs.BOM_UTF8) :]
    for encoding in ("utf-8", "cp1252"):
        try:
            return Decoded(raw.decode(encoding), encoding, bom)
        except UnicodeDecodeError:
            pass
    return Decoded(raw.decode("latin-1"), "latin-1", bom)


def decode_text(data: bytes | str) -> str:
    """Text of a program or points file (`decode_file`), with LF line ends.

    >>> decode_text(b"10 MOV P1\\r\\n20 END\\r\\n"), decode_text("caf\\xe9".encode("cp1252"))
    ('10 MOV P1\\n20 END\\n', 'café')
    """
    if isinstance(data, bytes):
        decoded = decode_file(data)
        # Not text: shown as it is (NULs and all), for the checker to say what is wrong.
        text = decoded.text if decoded.binary_at is None else data.decode("latin-1")
    else:
        text = data.removeprefix("\ufeff")
    return text.replace("\r\n", "\n").replace("\r", "\n")


__all__ = ["Decoded", "decode_file", "decode_text"]
