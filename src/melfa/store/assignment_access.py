"""Who may do what with an assignment: the one place it is decided (pure, no I/O).

Instructors and admins publish, manage and see every student's work; a student sees the
assignments published to the class or to their group, and works on (opens, checks,
submits) only their own copy. Every route asks `require` before it touches the store.
"""

from __future__ import annotations

from melfa.store.assignment_models import Assignment, AssignmentAction
from melfa.store.errors import AccessDenied
from melfa.store.models import User

__all__ = ["allowed", "published_to", "require"]


def published_to(user: User, assignment: Assignment) -> bool:
    """The assignment was handed to `user`: the whole class, or their group."""
    if assignment.group is None:
        return True
    return user.group is not None and user.group.lower() == assignment.group.lower()


def allowed(user: User, action: AssignmentAction, assignment: Assignment) -> bool:
    if user.disabled:
        return False
    if user.role.is_staff:
        return True
    if action is AssignmentAction.MANAGE:
        return False
    return published_to(user, assignment)


def require(user: User, action: AssignmentAction, assignment: Assignment) -> None:
    """`AccessDenied` unless `allowed`, in words that do not reveal the assignment."""
    if not allowed(user, action, assignment):
        if action is AssignmentAction.MANAGE:
            raise AccessDenied("only instructors manage assignments and see the class's work")
        raise AccessDenied(f"assignment {assignment.id} was not handed out to {user.username}")
