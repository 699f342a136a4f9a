"""Reading the real window the way a screen reader does: over AT-SPI, the Linux
accessibility bus, on the same X display as xdotool's key events.

Qt's xcb platform exports every widget to AT-SPI when ``QT_LINUX_ACCESSIBILITY_ALWAYS_ON``
is set; a status bar's accessible name is the message it shows (what Orca reads). A private
D-Bus session daemon (Debian's dbus-daemon) is started for the test, with its own
``XDG_RUNTIME_DIR``, so the accessibility bus it starts on demand (at-spi2-core's
at-spi-bus-launcher, through ``org.a11y.Bus``) is this test's alone; `dbus-send` (dbus-bin)
asks it. Nothing of melfa is changed for the test: it reads what any assistive technology
would.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

DBUS_DAEMON = shutil.which("dbus-daemon")
DBUS_SEND = shutil.which("dbus-send")
LAUNCHER = Path("/usr/libexec/at-spi-bus-launcher")
MISSING = [
    name
    for name, found in (
        ("dbus-daemon", DBUS_DAEMON),
        ("dbus-bin", DBUS_SEND),
        ("at-spi2-core", LAUNCHER.exists() or None),
    )
    if found is None
]
"""The Debian packages this reader needs and does not find (scripts/setup installs them)."""

_PAIR = re.compile(r'string "([^"]*)"\s+object path "([^"]*)"')
_STRING = re.compile(r'string "((?:[^"\\]|\\.)*)"')

REGISTRY = ("org.a11y.atspi.Registry", "/org/a11y/atspi/accessible/root")
ACCESSIBLE = "org.a11y.atspi.Accessible"


class Accessibility:
    """The accessibility bus of one private session: what a screen reader would see."""

    def __init__(self, env: dict[str, str]) -> None:
        self.env = env
        """The environment a Qt application exports its widgets in (add it to the app's)."""
        self._bar: tuple[str, str, str] | None = None
        """The status bar once found: (accessibility bus, its application, its path)."""

    def _ask(self, address: str, bus: str, path: str, method: str, *args: str) -> str:
        assert DBUS_SEND is not None
        done = subprocess.run(
            [DBUS_SEND, f"--bus={address}", "--print-reply", f"--dest={bus}", path, method, *args],
            capture_output=True,
            text=True,
            timeout=10,
            env=self.env,
        )
        if done.returncode != 0:
            raise LookupError(done.stderr.strip())
        return done.stdout

    def _address(self) -> str:
        out = self._ask(
            self.env["DBUS_SESSION_BUS_ADDRESS"],
            "org.a11y.Bus",
            "/org/a11y/bus",
            "org.a11y.Bus.GetAddress",
        )
        return str(_STRING.findall(out)[0])

    def find(self, role: str) -> list[tuple[str, str, str]]:
        """Every object of ``role`` (AT-SPI's role name, such as ``status bar``) in every
        application on the bus, as (accessibility bus, application, path)."""
        address = self._address()
        found = []
        stack = _PAIR.findall(self._ask(address, *REGISTRY, f"{ACCESSIBLE}.GetChildren"))
        while stack:
            bus, path = stack.pop()
            out = self._ask(address, bus, path, f"{ACCESSIBLE}.GetRoleName")
            if _STRING.findall(out)[0] == role:
                found.append((address, bus, path))
            stack += _PAIR.findall(self._ask(address, bus, path, f"{ACCESSIBLE}.GetChildren"))
        return found

    def name(self, address: str, bus: str, path: str) -> str:
        """An object's accessible name (what a screen reader says)."""
        out = self._ask(
            address,
            bus,
            path,
            "org.freedesktop.DBus.Properties.Get",
            f"string:{ACCESSIBLE}",
            "string:Name",
        )
        return str(_STRING.findall(out)[0]).replace('\\"', '"')

    def has_status_bar(self) -> bool:
        """Whether the one status bar on the bus is found (a walk of the whole window, once:
        then it is only read)."""
        if self._bar is None:
            try:
                bars = self.find("status bar")
            except (LookupError, IndexError):  # an application still registering
                return False
            self._bar = bars[0] if len(bars) == 1 else None
        return self._bar is not None

    def status_bar(self) -> str:
        """The message in the one status bar on the bus ("" while none is readable)."""
        if not self.has_status_bar():
            return ""
        assert self._bar is not None
        try:
            return self.name(*self._bar)
        except (LookupError, IndexError):  # gone: look for it again next time
            self._bar = None
            return ""


@contextmanager
def accessibility(env: dict[str, str]) -> Iterator[Accessibility]:
    """A private session bus for ``env``'s display; its accessibility bus is started on
    demand by the first application that asks for it."""
    assert DBUS_DAEMON is not None
    runtime = tempfile.mkdtemp(prefix="melfa-a11y-")  # short: a socket's path lives here
    read_fd, write_fd = os.pipe()
    proc = subprocess.Popen(
        [DBUS_DAEMON, "--session", "--nofork", f"--print-address={write_fd}"],
        pass_fds=(write_fd,),
        env={**env, "XDG_RUNTIME_DIR": runtime},
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    os.close(write_fd)
    with os.fdopen(read_fd) as pipe:
        address = pipe.readline().strip()  # written once the daemon listens
    try:
        assert address, "dbus-daemon did not start"
        yield Accessibility(
            {
                **env,
                "XDG_RUNTIME_DIR": runtime,
                "DBUS_SESSION_BUS_ADDRESS": address,
                "QT_LINUX_ACCESSIBILITY_ALWAYS_ON": "1",
                "NO_AT_BRIDGE": "0",
            }
        )
    finally:
        proc.terminate()
        proc.wait(timeout=10)
        shutil.rmtree(runtime, ignore_errors=True)
