"""The instructor's desk: what staff do from the IDE (accounts, the gate, the hold) as
audit actions, and the words the desk and the audit view show for them.

Pure: the web layer records a `DeskAction` as the audit entry's action (its value, e.g.
``account.add``) and the browser gets `DESK_WORDS` and `ACTION_WORDS` through ``/vocab.js``.
"""

from __future__ import annotations

import enum

__all__ = [
    "ACTION_WORDS",
    "DESK_WORDS",
    "VISIT_WORDS",
    "DeskAction",
    "SettingSource",
    "visit_refusal",
]


class DeskAction(enum.StrEnum):
    """What a member of staff did at the desk (and a sign-in, by anyone), as the audit log
    stores it beside the robot's commands (``robot.<command>``)."""

    SIGN_IN = "session.sign-in"
    ACCOUNT_ADD = "account.add"
    ACCOUNT_IMPORT = "account.import"
    ACCOUNT_PASSWORD = "account.password"
    ACCOUNT_REMOVE = "account.remove"
    GATE = "gate.set"
    HOLD = "desk.hold"
    RELEASE = "desk.release"
    EDIT_AS_STAFF = "workspace.edit-as-staff"
    READ_ONLY = "workspace.read-only"
    CELL = "cell.edit"
    LAB_NETWORK = "lab-network.set"


class SettingSource(enum.StrEnum):
    """Where a live setting of the lab robot (the gate, the lab's networks) came from, as
    the desk shows it (`melfa.service.live_settings`)."""

    DEFAULT = "default"
    """Nobody set it: gate off, anywhere."""
    COMMAND_LINE = "command-line"
    """The server's start-up option (``--require-simulation``, ``--lab-network``)."""
    DESK = "desk"
    """Staff chose it on the desk (saved: a restart keeps it, within the start-up option)."""


ACTION_WORDS: dict[DeskAction, str] = {
    DeskAction.SIGN_IN: "signed in",
    DeskAction.ACCOUNT_ADD: "added the account {who}",
    DeskAction.ACCOUNT_IMPORT: "imported a class list ({count} accounts)",
    DeskAction.ACCOUNT_PASSWORD: "set a new password for {who}",
    DeskAction.ACCOUNT_REMOVE: "removed the account {who}",
    DeskAction.GATE: "turned the simulation gate {state}",
    DeskAction.HOLD: "stopped the lab robot and held it",
    DeskAction.RELEASE: "released the lab robot",
    DeskAction.EDIT_AS_STAFF: "began editing {who}'s work ({workspace}) as instructor",
    DeskAction.READ_ONLY: "went back to reading {who}'s work ({workspace})",
    DeskAction.CELL: "edited the lab's cell ({obstacles} obstacles, {parts} parts)",
    DeskAction.LAB_NETWORK: "let students drive the lab robot from {networks}",
}
"""The audit view's sentence for each action (after the user's name); ``{who}`` is the
account, ``{count}`` how many were created, ``{state}`` on or off; a student's work
opened to edit names ``{who}`` and ``{workspace}``; a cell edit counts ``{obstacles}`` and
``{parts}``; ``{networks}`` the lab's networks (or "anywhere")."""

DESK_WORDS: dict[str, str] = {
    "title": "Instructor's desk",
    "page-title": "melfa · {title}",
    "to-classroom": "Assignments and class view",
    "to-ide": "Back to the IDE",
    "tabs": "Desk",
    "lab-robot": "Lab robot",
    "find": "Find",
    "find-label": "Find an account",
    "find-placeholder": "name or group",
    "username": "Username",
    "name": "Name",
    "group": "Group",
    "role": "Role",
    "last-sign-in": "Last sign-in",
    "actions": "Actions",
    "password": "Password",
    "passwords": "Passwords",
    "once-csv": "Download as CSV",
    "done": "Done",
    "cancel": "Cancel",
    "add-ok": "Add",
    "import-file": "Class list (CSV)",
    "audit-who": "Who",
    "audit-who-label": "Whose entries",
    "audit-who-placeholder": "username",
    "audit-show": "Show",
    "audit-show-label": "Which entries",
    "accounts": "Accounts",
    "add": "Add an account",
    "import": "Import a class list…",
    "import-help": (
        "A CSV file with a header row: username, name, group, and optionally role and "
        "password (generated when empty). The same file works with melfa users import."
    ),
    "import-ok": "Import",
    "importing": "Importing… (each password is hashed)",
    "imported": "{created} added, {skipped} already there.",
    "import-problem": "line {line}: {message}",
    "never": "never",
    "open-work": "Open work",
    "reset": "New password…",
    "reset-confirm": "Give {who} a new password? They are signed out everywhere.",
    "remove": "Remove…",
    "remove-confirm": "Remove the account {who}? Their sign-ins end now.",
    "removed": "{who} was removed.",
    "shown-once": "Hand these out now: they are shown only once and stored only as hashes.",
    "no-accounts": "No accounts you may manage yet.",
    "only-students": "As an instructor you manage students' accounts; an admin manages staff.",
    "not-yours": (
        "as {role} you may not manage {other} accounts (instructors manage students; admins "
        "manage everyone)"
    ),
    "gate": "Simulation gate",
    "gate-on": "On: a program must pass pre-flight before it is loaded onto the lab robot.",
    "gate-off": "Off: students may load onto the lab robot without a pre-flight.",
    "gate-turn-on": "Require pre-flight",
    "gate-turn-off": "Stop requiring pre-flight",
    "hold": "Stop and hold",
    "hold-title": "Stop and hold",
    "hold-free": "Students may drive the lab robot.",
    "held": "Held by {who}: the robot is stopped and no student's Run, Load or jog starts.",
    "release": "Release",
    "reset-alarm": "Reset alarm",
    "alarm-reset": "The alarm was reset.",
    "lab-network": "Where students drive from",
    "lab-network-anywhere": "Anywhere: a student may drive the lab robot from any computer "
    "that reaches this server.",
    "lab-network-only": "Only from {networks}: elsewhere students watch and use My "
    "simulator. STOP works from everywhere; staff are not restricted.",
    "lab-network-field": "The lab's networks",
    "lab-network-help": "Address and prefix, commas between (192.168.10.0/24).",
    "lab-network-you": "This computer: {address}",
    "lab-network-save": "Only from these",
    "lab-network-clear": "Allow anywhere",
    "lab-network-saved": "Saved: {networks}.",
    "from-default": "Nobody has changed this: it is the default.",
    "from-command-line": "Set when the server started ({flag}).",
    "from-desk": "Set by {who} on the desk, {when}. A restart keeps it.",
    "from-desk-until-restart": (
        "Set by {who} on the desk, {when}, until the server restarts: it starts with "
        "{flag}, and that applies again then."
    ),
    "from-desk-cut": (
        "Set by {who} on the desk, {when}, as {saved}; the server starts with {flag}, so "
        "only the part inside that holds."
    ),
    "from-desk-until-restart-cut": (
        "Set by {who} on the desk, {when}, until the server restarts: it starts with "
        "{flag}, and then only the part inside that holds."
    ),
    "anywhere": "anywhere",
    "audit": "Audit log",
    "audit-all": "everything",
    "audit-robot": "robot commands",
    "audit-control": "control changes",
    "audit-alarm": "alarms and the robot's link",
    "audit-refused": "refusals",
    "audit-queue": "the queue",
    "audit-desk": "accounts, gate, hold, cell and students' work",
    "audit-sign-in": "sign-ins",
    "audit-since": "Since",
    "audit-csv": "Export CSV",
    "audit-columns": "When,Who,Robot,What,Result",
    "audit-file": "audit.csv",
    "audit-by-melfa": "melfa",
    "result-ok": "done",
    "result-accepted": "asked (no answer yet)",
}
"""The desk's labels, help and confirmations (``{who}``: an account's name). Under each
setting, where it came from (``from-`` and a `SettingSource`; ``{who}`` set it, ``{when}``
in the browser's local time, ``{flag}`` the server's start-up option as written; ``-cut``:
the desk's networks, ``{saved}``, lie only partly inside it). ``not-yours``: the server's
refusal of an account ``{role}`` may not manage (of role ``{other}``; both
`melfa.vocab.roles` names, in lower case). ``audit-by-melfa``: who an
entry the service wrote on its own names (closing, a lost heartbeat)."""

VISIT_WORDS: dict[str, str] = {
    "reading": "You are reading {who}'s work ({workspace}): it is read-only.",
    "reading-help": (
        "Nothing you type here reaches their work. To change it, choose Edit as "
        "instructor: they see each edit as you make it, and the audit log records it."
    ),
    "edit": "Edit as instructor",
    "editing": "You are editing {who}'s work ({workspace}) as instructor.",
    "editing-help": "They see each edit as you make it; the audit log records that you edit.",
    "stop-editing": "Back to read-only",
    "open-in-editor": "Open in the editor",
    "refused": (
        "This is {who}'s work, open read-only: choose Edit as instructor first "
        "(the audit log records it)."
    ),
}
"""The banner over a student's workspace opened by staff, and the server's refusal of a
write before *Edit as instructor* (``{who}``: whose work, ``{workspace}``: its name)."""


def visit_refusal(who: str) -> str:
    """The refusal of a write by staff who have not chosen to edit ``who``'s work."""
    return VISIT_WORDS["refused"].format(who=who)
