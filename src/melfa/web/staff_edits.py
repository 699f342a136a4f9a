"""Staff reading a student's work: read-only unless they asked to edit it.

An instructor may open every workspace, but what they type must never land in a student's
work by accident. So a member of staff who is not one of the workspace's owners reads it
only; every write (a save, a restore, an import, a rename, a live edit) is refused by the
server until they choose *Edit as instructor* (audited by the route that grants it). The
grant belongs to one sign-in and one workspace, and ends with the sign-in or when they go
back to reading. Kept in memory: a restarted server is read-only again, the safe side.
"""

from __future__ import annotations

from melfa.store import Session, Workspace
from melfa.store.workspaces import Workspaces

__all__ = ["StaffEdits"]


class StaffEdits:
    """Which sign-ins of staff chose to edit which workspaces of others."""

    def __init__(self) -> None:
        self._granted: dict[str, set[int]] = {}

    @staticmethod
    def visiting(session: Session, workspace: Workspace) -> bool:
        """Staff looking at a workspace that is not theirs nor their group's."""
        return session.user.role.is_staff and not Workspaces.is_member(session.user, workspace)

    def grant(self, session: Session, workspace_id: int) -> None:
        self._granted.setdefault(session.id, set()).add(workspace_id)

    def revoke(self, session: Session, workspace_id: int) -> None:
        ids = self._granted.get(session.id)
        if ids is not None:
            ids.discard(workspace_id)
            if not ids:
                del self._granted[session.id]

    def editing(self, session: Session, workspace: Workspace) -> bool:
        """Staff chose to edit this workspace of someone else in this sign-in."""
        return workspace.id in self._granted.get(session.id, ())

    def may_write(self, session: Session, workspace: Workspace) -> bool:
        """Members write; staff visiting only once they asked to (`grant`)."""
        return not self.visiting(session, workspace) or self.editing(session, workspace)
