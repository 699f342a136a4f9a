"""Workspace names: the rules a name follows, one place (pure, no I/O).

A user may keep several personal workspaces ("My programs", "pyramid", "exam practice");
each is named by its owner, unique per owner without regard to case. A group's shared
workspace is named after the group until someone renames it.
"""

from __future__ import annotations

import unicodedata

from melfa.store.errors import InvalidValue

__all__ = ["DEFAULT_PERSONAL_NAME", "MAX_NAME_CHARS", "clean_name"]

DEFAULT_PERSONAL_NAME = "My programs"
"""The name of a user's first (default) workspace."""

MAX_NAME_CHARS = 60
"""Long enough for "Pyramid with gripper, second try", short enough for a menu."""


def clean_name(name: str) -> str:
    """The name as stored (surrounding and repeated spaces dropped), or `InvalidValue`
    saying what is wrong in the student's words."""
    cleaned = " ".join(name.split())
    if not cleaned:
        raise InvalidValue("name", "a workspace needs a name")
    if len(cleaned) > MAX_NAME_CHARS:
        raise InvalidValue(
            "name",
            f"is {len(cleaned)} characters long; a workspace name has at most {MAX_NAME_CHARS}",
        )
    if any(unicodedata.category(ch).startswith("C") for ch in cleaned):
        raise InvalidValue("name", "must not contain control characters")
    return cleaned
