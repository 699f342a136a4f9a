"""The student's words for the browser, from `melfa.vocab` (one vocabulary for every
client): ``/vocab.js``, an ES module the IDE imports. The server sends codes (an activity,
why a jog ended, a command, the link's state); the browser shows the words of the code it
was sent, filled the same way the desktop client fills them (`melfa.vocab.activity.said`)."""

from __future__ import annotations

import dataclasses
import json
from typing import Any

from fastapi import APIRouter
from fastapi.responses import Response

from melfa.protocol.advice import FIX_LABELS
from melfa.vocab.account import ACCOUNT_WORDS
from melfa.vocab.activity import ACTIVITY_WORDS, FRAME_WORDS, WHERE_WORDS
from melfa.vocab.classroom import (
    CLASS_VIEW_WORDS,
    COLUMN_WORDS,
    FILTER_WORDS,
    GRADE_WORDS,
    GRADED_WORDS,
    PANE_WORDS,
    RESULT_WORDS,
    STUCK_AFTER_MIN,
)
from melfa.vocab.commands import Command
from melfa.vocab.desk import ACTION_WORDS, DESK_WORDS, VISIT_WORDS
from melfa.vocab.guide import GUIDE_WORDS
from melfa.vocab.ide import HEADER_LINK_WORDS, IDE_WORDS
from melfa.vocab.jog import JOG_END_UNKNOWN, JogEnd
from melfa.vocab.lease import CONTROL_WORDS, HolderState, LeaseReason
from melfa.vocab.link import LINK_UNKNOWN, LINK_WORDS
from melfa.vocab.queue import QUEUE_WORDS, EntryState, QueueStep
from melfa.vocab.refusals import Asked
from melfa.vocab.robot_log import NOTE_WORDS, ROBOT_LOG_WORDS
from melfa.vocab.roles import ROLE_WORDS
from melfa.vocab.runs import RunOutcome
from melfa.vocab.signout import SIGN_OUT_WORDS
from melfa.vocab.slot import SLOT_WORDS
from melfa.vocab.start import PLACE_WORDS, SERVO_WORDS, START_WORDS
from melfa.vocab.targets import TARGET_LABELS, TARGET_WORDS

router = APIRouter(include_in_schema=False)


def vocabulary() -> dict[str, Any]:
    """Every family of words, keyed by its wire value."""
    return {
        "ACTIVITY": {
            activity.value: {
                "said": words.said,
                "bare": words.bare,
                "pill": words.pill,
                "tone": words.tone.value,
                "hint": words.hint,
            }
            for activity, words in ACTIVITY_WORDS.items()
        },
        "FRAME_WORDS": FRAME_WORDS,
        "WHERE_WORDS": WHERE_WORDS,
        "LINK_WORDS": {status.value: words for status, words in LINK_WORDS.items()},
        "LINK_UNKNOWN": LINK_UNKNOWN,
        "COMMANDS": {
            c.value: {
                "label": c.label,
                "moves": c.moves,
                "detail": c.detail_in_words,
                "queue": c.queue,
                "control": c.control,
            }
            for c in Command
        },
        "JOG_ENDS": {e.value: {"words": e.template, "expected": e.expected} for e in JogEnd},
        "JOG_END_UNKNOWN": JOG_END_UNKNOWN,
        "LEASE_REASONS": {r.value: {"words": r.template} for r in LeaseReason},
        "HOLDER_STATES": {h.value: h.words for h in HolderState},
        "CONTROL_WORDS": dataclasses.asdict(CONTROL_WORDS),
        "RUN_OUTCOMES": {o.value: {"words": o.words} for o in RunOutcome},
        "QUEUE_STEPS": {q.value: {"words": q.template} for q in QueueStep},
        "QUEUE_STATES": {e.value: {"words": e.words} for e in EntryState},
        "QUEUE_WORDS": dataclasses.asdict(QUEUE_WORDS),
        "GRADE_WORDS": {kind.value: words for kind, words in GRADE_WORDS.items()},
        "GRADED_WORDS": {kind.value: words for kind, words in GRADED_WORDS.items()},
        "CLASS_COLUMNS": {column.value: words for column, words in COLUMN_WORDS.items()},
        "CLASS_FILTERS": {
            f.value: {"label": words.label, "hint": words.hint} for f, words in FILTER_WORDS.items()
        },
        "RESULT_WORDS": RESULT_WORDS,
        "PANE_WORDS": PANE_WORDS,
        "CLASS_VIEW_WORDS": CLASS_VIEW_WORDS,
        "STUCK_AFTER_MIN": STUCK_AFTER_MIN,
        "DESK_WORDS": DESK_WORDS,
        "VISIT_WORDS": VISIT_WORDS,
        "NOTE_WORDS": NOTE_WORDS,
        "ROBOT_LOG_WORDS": ROBOT_LOG_WORDS,
        "AUDIT_ACTIONS": {action.value: words for action, words in ACTION_WORDS.items()},
        "START_WORDS": START_WORDS,
        "START_SERVO": {servo.value: words for servo, words in SERVO_WORDS.items()},
        "START_PLACE": {place.value: words for place, words in PLACE_WORDS.items()},
        "SLOT_WORDS": SLOT_WORDS,
        "SIGN_OUT_WORDS": SIGN_OUT_WORDS,
        "GUIDE_WORDS": GUIDE_WORDS,
        "IDE_WORDS": IDE_WORDS,
        "HEADER_LINK_WORDS": {status.value: words for status, words in HEADER_LINK_WORDS.items()},
        "ROLE_WORDS": ROLE_WORDS,
        "FIX_LABELS": {fix.value: label for fix, label in FIX_LABELS.items()},
        "REFUSAL_ASKED": {asked.value: {"after_fix": asked.after_fix} for asked in Asked},
        "TARGET_LABELS": TARGET_LABELS,
        "TARGET_WORDS": TARGET_WORDS,
        "ACCOUNT_WORDS": ACCOUNT_WORDS,
    }


def vocab_module() -> str:
    """The ES module text: one ``export const`` per family."""
    lines = ["// Generated from melfa.vocab (the words every client shows for the server's codes)."]
    for name, table in vocabulary().items():
        lines.append(f"export const {name} = {json.dumps(table, ensure_ascii=False)};")
    return "\n".join(lines) + "\n"


@router.get("/vocab.js")
async def vocab_js() -> Response:
    return Response(vocab_module(), media_type="text/javascript")


__all__ = ["router", "vocab_module", "vocabulary"]
