"""Typed errors of the store, each saying whose fault it is.

`StoreError` is the root. Subclasses that describe a *caller's* mistake (bad input, a
conflict, an unknown name) are `UserInputError`s: the web layer turns them into 4xx
responses and the CLI into one red line. Anything else (`DatabaseError`) is ours or the
disk's, and becomes a 5xx.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from melfa.lang.diagnostics import Diagnostic
    from melfa.store.models import Revision

__all__ = [
    "AccessDenied",
    "AlreadyExists",
    "DatabaseError",
    "InvalidValue",
    "NotFound",
    "SaveConflict",
    "StoreError",
    "TransferError",
    "UserInputError",
    "WrongExtension",
]


class StoreError(Exception):
    """Anything the store refuses or fails to do."""


class DatabaseError(StoreError):
    """The database file is unusable: newer schema, an edited migration, a disk error."""


class UserInputError(StoreError):
    """The caller asked for something invalid; the message says what (a 4xx)."""


class InvalidValue(UserInputError):
    """A field breaks its rules (username, password length, role, text size)."""

    def __init__(self, field: str, message: str) -> None:
        super().__init__(f"{field}: {message}")
        self.field = field


class NotFound(UserInputError):
    """No such user, group, workspace or revision."""


class AlreadyExists(UserInputError):
    """The name is taken."""


class AccessDenied(UserInputError):
    """The user may not touch this workspace."""


class SaveConflict(UserInputError):
    """The save was based on an old revision; `current` is what is stored now.

    Two browser tabs editing one workspace: the second save is refused instead of silently
    replacing the first; the client shows `current` and lets the student choose.
    """

    def __init__(self, base: int, current: Revision) -> None:
        super().__init__(
            f"the workspace changed since revision {base}: it is now at revision "
            f"{current.number} (saved by {current.author or 'a removed user'}); "
            "reload it or save again on top of it"
        )
        self.base = base
        self.current = current


class TransferError(UserInputError):
    """An imported or exported file cannot be converted without changing its meaning.

    `diagnostics` carry line and column, in the same shape as `melfa check`.
    """

    def __init__(self, filename: str, message: str, diagnostics: tuple[Diagnostic, ...]) -> None:
        super().__init__(f"{filename}: {message}")
        self.filename = filename
        self.diagnostics = diagnostics


class WrongExtension(UserInputError):
    """A file of the wrong kind was given (e.g. a `.txt` where a `.MB4` belongs)."""

    def __init__(self, filename: str, expected: str) -> None:
        super().__init__(f"{filename}: expected a {expected} file")
        self.filename = filename
        self.expected = expected
