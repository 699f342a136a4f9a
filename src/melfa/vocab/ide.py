"""The IDE's own words around the robot: the header's connections, the user menu, the main
buttons' toasts and confirmations, the *Robot control* tab's facts and what each failed
request is called.

Pure: the browser gets `IDE_WORDS` and `HEADER_LINK_WORDS` through ``/vocab.js``
(``static/js/main.js`` shows them). ``{placeholders}`` are filled by the page: ``{user}``,
``{role}`` (`melfa.vocab.roles`), ``{name}`` a saved file, ``{bytes}`` sent, ``{point}`` a
point's name, ``{line}`` a line of the editor, ``{percent}``.
"""

from __future__ import annotations

from melfa.vocab.link import LinkStatus

__all__ = ["HEADER_LINK_WORDS", "IDE_WORDS"]

HEADER_LINK_WORDS: dict[LinkStatus, str] = {
    LinkStatus.CONNECTED: "connected",
    LinkStatus.CONNECTING: "connecting",
    LinkStatus.RECONNECTING: "reconnecting",
    LinkStatus.LOST: "lost",
    LinkStatus.CLOSED: "closed",
}
"""The header's *Robot* light, after its label ("Robot connected"); the full sentence of
each is `melfa.vocab.link.LINK_WORDS`, in the light's tooltip and the status bar."""

IDE_WORDS: dict[str, str] = {
    # the header: the two connection lights, the user menu
    "server": "Server",
    "robot": "Robot",
    "server-connected": "connected",
    "server-connecting": "connecting…",
    "server-disconnected": "disconnected",
    "robot-unknown": "unknown",
    "status-label": "{what} {text}. Click to reconnect.",
    "status-title": "{what}: {text}. Click to reconnect.",
    "status-title-detail": "{what}: {text} ({detail}). Click to reconnect.",
    "signed-in-as": "Signed in as {user} · {role}",
    "open-workspace-failed": "Could not open your workspace",
    "server-unreachable": "Could not reach the server",
    "socket-lost": "connection lost",
    "socket-retargeted": "target changed",
    "socket-closed": "not connected to the server",
    "socket-timeout": "no answer from the server",
    "close": "Close",
    # STOP
    "stop-failed": "STOP could not be delivered",
    "stop-sent": "Stop sent",
    "stop-sent-text": "The robot stops; queued commands are cancelled.",
    # the main buttons
    "stop-program-failed": "Could not stop",
    "saved": "Saved {name}",
    "saved-program": "Numbered 10, 20, 30…; jumps rewritten to match.",
    "saved-points": "Points in the controller's format.",
    "save-failed": "Could not save the file",
    "save-program": "Save .MB4",
    "save-points": "Save .POS",
    "save-program-hint": "Download the numbered .MB4",
    "save-points-hint": "Download the points as .POS",
    "loading": "Loading project…",
    "loading-share": "Loading project… {percent} %",
    "loaded": "Project loaded",
    "loaded-text": "Program and points are in slot 1 ({bytes} bytes).",
    "load-failed": "Load failed",
    "load-program-errors": "Not loaded: the program has errors",
    "load-points-errors": "Not loaded: the points have errors",
    "load-could-not": "Could not load the project",
    "run-failed": "Could not run the program",
    # the alarm banner
    "alarm": "Alarm",
    "show-line": "Show line {line}",
    "reset-alarm-failed": "Could not reset the alarm",
    "alarm-was-reset": "Alarm reset",
    "alarm-was-reset-text": "The controller is ready again.",
    # the Robot control tab
    "on": "on",
    "off": "off",
    "hand-open": "open",
    "hand-closed": "closed",
    "flags": "FL1 {fl1}, FL2 {fl2}",
    "speed": "{speed} mm/s",
    "percent": "{percent} %",
    "pose-measured": "read from the controller",
    "pose-computed": "computed from the joints",
    "servo-on-failed": "Could not switch the servo on",
    "servo-off-failed": "Could not switch the servo off",
    "hand-failed": "Could not move the hand",
    "override-failed": "Could not set the override",
    "reset-program-failed": "Could not reset the program",
    "delete-confirm": "Delete the program and its points from the controller's slot 1?",
    "delete-failed": "Could not delete the program",
    "no-points": "no points defined",
    "move-failed-to": "Could not move to {point}",
    "moving-to": "Moving to {point}…",
    "move-failed": "Move failed",
}
"""The IDE's words outside the families it shares with other views (queue, control, the
activity line …, each in its own module)."""
