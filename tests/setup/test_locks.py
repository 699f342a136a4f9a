"""The set-up's lock files: the server's (scripts/serve) holds what `melfa serve` needs and
nothing of the test tools or the desktop; the desktop's adds the desktop; every package has
one version and one set of hashes across the three (scripts/lock makes them together)."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PIN = re.compile(r"^([A-Za-z0-9_.\-]+)==(\S+) \\$")


def pins(name: str) -> dict[str, tuple[str, frozenset[str]]]:
    """package → (version, hashes) of one lock file."""
    found: dict[str, tuple[str, frozenset[str]]] = {}
    package = ""
    for line in (ROOT / name).read_text(encoding="utf-8").splitlines():
        pin = PIN.match(line)
        if pin:
            package = pin.group(1).lower().replace("_", "-")
            found[package] = (pin.group(2), frozenset())
        elif "--hash=sha256:" in line and package:
            version, hashes = found[package]
            found[package] = (version, hashes | {line.split("--hash=")[1].rstrip(" \\")})
    return found


def names(requirements: list[str]) -> set[str]:
    return {re.split(r"[<>=\[ ;]", r, maxsplit=1)[0].lower() for r in requirements}


PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
FULL, SERVE, DESKTOP = (
    pins(n) for n in ("requirements.lock", "requirements-serve.lock", "requirements-desktop.lock")
)


def test_the_smaller_locks_pin_what_the_full_lock_pins() -> None:
    assert len(FULL) > len(DESKTOP) > len(SERVE) > 20
    for lock in (SERVE, DESKTOP):
        for package, pinned in lock.items():
            assert FULL.get(package) == pinned, package  # same version, same hashes


def test_the_server_lock_holds_the_server_and_nothing_else() -> None:
    runtime = names(PROJECT["dependencies"])
    assert runtime <= set(SERVE)
    extras = PROJECT["optional-dependencies"]
    for extra in ("dev", "desktop"):
        only_there = names(extras[extra]) - runtime
        assert only_there and not only_there & set(SERVE), (extra, only_there & set(SERVE))
    assert names(extras["desktop"]) <= set(DESKTOP)
    assert not (names(extras["dev"]) - runtime) & set(DESKTOP)


def test_serve_installs_the_server_lock_and_test_the_full_one() -> None:
    serve = (ROOT / "scripts" / "serve").read_text(encoding="utf-8")
    assert "scripts/setup --serve" in serve
    test = (ROOT / "scripts" / "test").read_text(encoding="utf-8")
    assert re.search(r"^scripts/setup$", test, re.MULTILINE)
    setup = (ROOT / "scripts" / "setup").read_text(encoding="utf-8")
    assert "--serve) LOCK=requirements-serve.lock" in setup
    assert "--desktop) LOCK=requirements-desktop.lock" in setup
