"""Who an account is (a student, an instructor, an admin, an observer), in words.

Pure: the server sends a role's code (``student``, the value of `melfa.store.models.Role`
and `melfa.service.actors.Role`); the desk's account list and its *Add an account* form,
the IDE's user menu, the header's "who holds control" and the desktop client's header show
`ROLE_WORDS` of it, never the code (tests/web/test_vocab.py holds the two enums to it).
"""

from __future__ import annotations

__all__ = ["ROLE_WORDS", "role_words"]

ROLE_WORDS: dict[str, str] = {
    "student": "Student",
    "instructor": "Instructor",
    "admin": "Admin",
    "observer": "Observer",
}
"""Each role's code and its name."""


def role_words(code: str) -> str:
    """The role's name; an unknown code as it came (a newer server's role, still readable)."""
    return ROLE_WORDS.get(code, code)
