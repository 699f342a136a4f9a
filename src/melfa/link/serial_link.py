"""RS-232 through pyserial: a device path or any pyserial URL (``socket://``, ``loop://``,
``rfc2217://``, ``spy://``…), opened with the `LinkSettings` (9600 8E2 by default)."""

from __future__ import annotations

import contextlib
import errno
import termios

import serial

from melfa.link.base import POLL_S, Link
from melfa.link.errors import BUSY_HINT, LinkBusy, LinkClosed, LinkError
from melfa.link.settings import LinkSettings

UNPLUGGED_HINT = "the adapter was unplugged, or the other end of the line went away"


class SerialLink(Link):
    """A pyserial port. Blocked reads wake through pyserial's `cancel_read` where it exists."""

    def __init__(self, url: str, settings: LinkSettings | None = None) -> None:
        settings = settings or LinkSettings()
        super().__init__(settings, f"{url} ({settings.describe()})")
        self.url = url
        # A device path is locked while open (pyserial's flock), so a second process is
        # told the port is held rather than sharing the line and losing replies.
        options = settings.pyserial_kwargs()
        if "://" not in url:
            options["exclusive"] = True
        try:
            port = serial.serial_for_url(url, do_not_open=True, timeout=POLL_S, **options)
            port.open()
        except termios.error as exc:
            code, text = (*exc.args, None, str(exc))[:2]
            if code == errno.EINVAL and url.startswith("/dev/pts/"):
                # A pty another process holds refuses the line settings.
                raise LinkBusy(f"cannot open {url}: {BUSY_HINT}") from None
            raise LinkError(
                f"cannot set {settings.describe()} on {url} ({text}): is it a serial port?"
            ) from None
        except (serial.SerialException, OSError, ValueError) as exc:
            if "exclusively lock" in str(exc) or getattr(exc, "errno", None) == errno.EBUSY:
                raise LinkBusy(f"cannot open {url}: {BUSY_HINT}") from None
            raise LinkError(f"cannot open {url} at {settings.describe()}: {exc}") from None
        self.port = port

    def _write(self, data: bytes) -> None:
        try:
            self.port.write(data)
        except (serial.SerialException, OSError) as exc:
            raise self._dead(exc) from None

    def _read(self, timeout: float) -> bytes:
        try:
            data = bytes(self.port.read(1))
            if data:
                waiting = self.port.in_waiting
                if waiting:
                    data += bytes(self.port.read(waiting))
        except (serial.SerialException, OSError, TypeError) as exc:
            # TypeError: pyserial's posix read after a concurrent close (fd is None).
            raise self._dead(exc) from None
        return data

    def _read_ready(self) -> bytes:
        try:
            waiting = self.port.in_waiting
            return bytes(self.port.read(waiting)) if waiting else b""
        except (serial.SerialException, OSError, TypeError) as exc:
            raise self._dead(exc) from None

    def _dead(self, exc: BaseException) -> LinkError:
        if self._closed:
            return LinkClosed(f"{self.url} is closed")
        text = str(exc)
        if (
            "returned no data" in text
            or f"Errno {errno.EIO}" in text
            or getattr(exc, "errno", None) == errno.EIO
        ):
            return LinkClosed(f"{self.url} stopped responding: {UNPLUGGED_HINT} ({text})")
        return LinkError(f"{self.url}: {text}")

    def _wake(self) -> None:
        cancel = getattr(self.port, "cancel_read", None)
        if cancel is not None:
            with contextlib.suppress(serial.SerialException, OSError):
                cancel()

    def _close(self) -> None:
        with contextlib.suppress(serial.SerialException, OSError):
            self.port.close()
