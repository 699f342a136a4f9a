"""Password hashing (Argon2id via argon2-cffi), rules, and generated passwords.

Hashing happens on the caller's thread, never inside a write transaction, so a slow hash
does not hold up other writes.
"""

from __future__ import annotations

import functools
import re
import secrets
from pathlib import Path

from argon2 import PasswordHasher
from argon2.exceptions import InvalidHashError, VerificationError, VerifyMismatchError

from melfa.store.errors import InvalidValue

__all__ = [
    "GENERATED_ALPHABET",
    "MAX_PASSWORD_LENGTH",
    "MIN_PASSWORD_LENGTH",
    "Passwords",
    "check_password_rules",
    "generate_password",
    "weakness",
]

MIN_PASSWORD_LENGTH = 8
MAX_PASSWORD_LENGTH = 256
"""Long enough for any passphrase; short enough that hashing cannot be used to stall us."""

GENERATED_ALPHABET = "abcdefghjkmnpqrstuvwxyzACDEFGHJKLMNPQRTUVWXY34679"
"""No look-alikes (0/O, 1/l/I, 5/S, 2/Z, 8/B): generated passwords are handed out on paper."""


COMMON_PASSWORDS = Path(__file__).with_name("common-passwords.txt")
"""The bundled list of common passwords (a small sample of public top lists)."""
_TAIL = re.compile(r"[\d\W_]+\Z")


@functools.cache
def _common() -> frozenset[str]:
    lines = COMMON_PASSWORDS.read_text(encoding="utf-8").splitlines()
    return frozenset(w.strip().lower() for w in lines if w.strip() and not w.startswith("#"))


def weakness(password: str, username: str = "") -> str | None:
    """Why ``password`` is too easy to guess, or None.

    >>> weakness("password"), weakness("Password2026!")
    ('is one of the most common passwords', 'is one of the most common passwords')
    >>> weakness("aaaaaaaa")
    'repeats one character'
    >>> weakness("ada12345", "ada"), weakness("mK4x-ha9T-wqcE")
    ('is your username with a few characters added', None)
    """
    lowered = password.lower()
    stem = _TAIL.sub("", lowered)
    common = _common()
    if lowered in common or (len(stem) >= 4 and (stem in common or stem + "1" in common)):
        return "is one of the most common passwords"
    if len(set(lowered)) <= 2:
        return "repeats one character"
    name = username.strip().lower()
    if name and (lowered == name or stem == name or stem == name[::-1]):
        return "is your username with a few characters added"
    return None


def check_password_rules(password: str, username: str = "") -> None:
    """Raise `InvalidValue` unless `password` is acceptable (long enough, not common, not
    the username)."""
    if len(password) < MIN_PASSWORD_LENGTH:
        raise InvalidValue("password", f"must be at least {MIN_PASSWORD_LENGTH} characters")
    if len(password) > MAX_PASSWORD_LENGTH:
        raise InvalidValue("password", f"must be at most {MAX_PASSWORD_LENGTH} characters")
    if any(ord(ch) < 32 or ord(ch) == 127 for ch in password):
        raise InvalidValue("password", "must not contain control characters")
    why = weakness(password, username)
    if why is not None:
        raise InvalidValue(
            "password", f"{why}: choose a longer phrase of unrelated words (or generate one)"
        )


def generate_password(groups: int = 3, size: int = 4) -> str:
    """A random password like ``mK4x-ha9T-wqcE`` (about 67 bits with the defaults).

    >>> p = generate_password(); len(p), p.count("-")
    (14, 2)
    """
    return "-".join(
        "".join(secrets.choice(GENERATED_ALPHABET) for _ in range(size)) for _ in range(groups)
    )


class Passwords:
    """Hash and verify; `hasher` is injectable so tests can use cheap parameters."""

    def __init__(self, hasher: PasswordHasher | None = None) -> None:
        self.hasher = hasher if hasher is not None else PasswordHasher()
        self._dummy: str | None = None

    def hash(self, password: str) -> str:
        return self.hasher.hash(password)

    def verify(self, stored_hash: str, password: str) -> bool:
        """True when `password` matches; a damaged hash counts as no match."""
        try:
            return self.hasher.verify(stored_hash, password)
        except (VerifyMismatchError, VerificationError, InvalidHashError):
            return False

    def needs_rehash(self, stored_hash: str) -> bool:
        """The hash was made with older parameters and should be replaced on login."""
        try:
            return self.hasher.check_needs_rehash(stored_hash)
        except InvalidHashError:
            return True

    def burn(self, password: str) -> None:
        """Spend the time of one verification, so an unknown username is not faster."""
        if self._dummy is None:
            self._dummy = self.hasher.hash(generate_password())
        self.verify(self._dummy, password)
