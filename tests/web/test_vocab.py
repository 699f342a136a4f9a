"""The browser's words are melfa.vocab's: the IDE imports /vocab.js (generated), shows the
words of the codes the server sends, and parses no English (no reason picked apart)."""

from __future__ import annotations

import json
import re

from melfa.vocab.activity import ACTIVITY_WORDS, Activity
from melfa.vocab.commands import Command
from melfa.vocab.jog import JogEnd
from melfa.vocab.link import LINK_WORDS, LinkStatus
from melfa.web.routes.pages import STATIC
from tests.web.conftest import Web


def test_the_browsers_vocabulary_is_melfa_vocab(web: Web) -> None:
    reply = web.client.get("/vocab.js")
    assert reply.status_code == 200 and "javascript" in reply.headers["content-type"]
    tables = {k: json.loads(v) for k, v in re.findall(r"export const (\w+) = (.*);", reply.text)}
    assert set(tables["ACTIVITY"]) == {a.value for a in Activity}
    assert tables["ACTIVITY"]["moving-to"]["said"] == ACTIVITY_WORDS[Activity.MOVING_TO].said
    move_to = {"label": "Move to", "moves": True, "detail": False, "queue": False, "control": False}
    assert tables["COMMANDS"]["move_to"] == move_to
    queue = {c for c, words in tables["COMMANDS"].items() if words["queue"]}
    assert queue == {"join_queue", "claim_turn", "leave_queue", "give_back"}
    control = {c for c, words in tables["COMMANDS"].items() if words["control"]}
    assert control == {"take_control"}
    assert set(tables["JOG_ENDS"]) == {e.value for e in JogEnd}
    assert tables["JOG_ENDS"]["stopped"]["words"] == JogEnd.STOPPED.template
    assert tables["LINK_WORDS"]["lost"] == LINK_WORDS[LinkStatus.LOST]
    assert set(tables["COMMANDS"]) == {c.value for c in Command}


def test_no_script_names_a_commands_audit_entry() -> None:
    """Which commands' entries go under a filter of the desk's audit (the queue's requests,
    taking control) is a flag of `melfa.vocab.commands.Command` read from /vocab.js's
    COMMANDS, never a list of ``robot.<command>`` names in a script (one home: a new one
    joins the filter by its flag)."""
    named = re.compile(r"robot\.(" + "|".join(c.value for c in Command) + r")\b")
    found = [
        f"{path.name}:{n}: {line.strip()}"
        for path in sorted((STATIC / "js").glob("*.js"))
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if named.search(line)
    ]
    assert not found, "read the command's flag from COMMANDS instead:\n" + "\n".join(found)


def test_the_ide_parses_no_reasons() -> None:
    """Reasons arrive as codes: no script picks a sentence apart."""
    for path in sorted((STATIC / "js").glob("*.js")):
        text = path.read_text(encoding="utf-8")
        assert not re.search(r"reason\??\.(startsWith|slice|split|includes)", text), path.name
        assert "m.reason" not in text, path.name
