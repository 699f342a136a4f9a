"""The queue's rules as pure logic (`melfa.service.queue.TurnQueue`): time is the ``now``
each call is given."""

from __future__ import annotations

import pytest

from melfa.service.queue import Entry, QueueError, QueueSettings, TurnQueue
from melfa.vocab.queue import EntryState, QueueStep, TurnEnd
from melfa.vocab.refusals import Refusal

SETTINGS = QueueSettings(claim_s=60, turn_s=240, grace_s=120, warn_s=30, overhead_s=40)


def entry(user: str, cycle_s: float | None = 20.0, now: float = 0.0, text: str = "END") -> Entry:
    return Entry(user, "student", text, "", f"p-{text}", "pts", cycle_s, now, workspace_id=7)


def everyone(_: str) -> bool:
    return True


def kinds(steps: list) -> list[QueueStep]:  # type: ignore[type-arg]
    return [s.kind for s in steps]


def queue_of(*users: str) -> TurnQueue:
    q = TurnQueue(SETTINGS)
    for user in users:
        q.join(entry(user))
    return q


def test_the_head_is_offered_and_a_claim_starts_a_turn() -> None:
    q = queue_of("ann", "bob", "cat")
    assert q.active
    steps = q.tick(10.0, everyone, False)
    assert kinds(steps) == [QueueStep.OFFERED]
    assert q.entries[0].state is EntryState.OFFERED
    assert q.entries[0].offered_until == 70.0
    with pytest.raises(QueueError) as refused:
        q.claim("bob", 11.0)
    assert refused.value.reason is Refusal.NOT_YOUR_TURN
    assert kinds(q.claim("ann", 12.0)) == [QueueStep.CLAIMED]
    assert q.turn is not None and q.turn.user == "ann" and q.turn.ends == 252.0
    assert [e.user for e in q.entries] == ["bob", "cat"]
    assert q.tick(13.0, everyone, False) == []  # nobody else is offered while ann has the arm


def test_a_missed_claim_moves_back_one_place_not_out() -> None:
    q = queue_of("ann", "bob", "cat")
    q.tick(0.0, everyone, False)
    assert q.tick(59.9, everyone, False) == []
    steps = q.tick(60.0, everyone, False)
    assert kinds(steps) == [QueueStep.MISSED, QueueStep.OFFERED]
    assert steps[0].user == "ann" and steps[0].position == 2
    assert [e.user for e in q.entries] == ["bob", "ann", "cat"]
    assert q.entries[1].missed == 1
    assert steps[1].user == "bob"


def test_a_turn_is_warned_then_ends_on_time_and_the_next_is_offered() -> None:
    q = queue_of("ann", "bob")
    q.tick(0.0, everyone, False)
    q.claim("ann", 0.0)
    assert q.tick(209.0, everyone, False) == []
    warned = q.tick(210.0, everyone, False)
    assert kinds(warned) == [QueueStep.WARNED] and warned[0].seconds == 30.0
    ended = q.tick(240.0, everyone, False)
    assert kinds(ended) == [QueueStep.ENDED, QueueStep.OFFERED]
    assert not ended[0].stop and ended[1].user == "bob"


def test_a_program_running_at_the_end_is_stopped_or_finishes_per_the_setting() -> None:
    q = queue_of("ann")
    q.tick(0.0, everyone, False)
    q.claim("ann", 0.0)
    stopped = q.tick(240.0, everyone, True)
    assert kinds(stopped) == [QueueStep.STOPPED] and stopped[0].stop
    assert not q.active

    q = TurnQueue(QueueSettings(at_turn_end=TurnEnd.FINISH, finish_cap_s=100))
    q.join(entry("ann"))
    q.tick(0.0, everyone, False)
    q.claim("ann", 0.0)
    assert kinds(q.tick(240.0, everyone, True)) == [QueueStep.ENDING]
    assert q.turn is not None and q.turn.ending
    assert q.tick(300.0, everyone, True) == []
    assert kinds(q.tick(310.0, everyone, False)) == [QueueStep.ENDED]  # it finished
    q.join(entry("ann"))
    q.tick(400.0, everyone, False)
    q.claim("ann", 400.0)
    q.tick(640.0, everyone, True)
    capped = q.tick(740.0, everyone, True)
    assert kinds(capped) == [QueueStep.STOPPED] and capped[0].stop


def test_grace_keeps_a_place_then_drops_it() -> None:
    q = queue_of("ann", "bob")
    here = {"ann": True, "bob": False}
    assert kinds(q.tick(0.0, here.__getitem__, False)) == [QueueStep.AWAY, QueueStep.OFFERED]
    here["bob"] = True
    assert kinds(q.tick(100.0, here.__getitem__, False)) == [
        QueueStep.BACK,
        QueueStep.MISSED,
        QueueStep.OFFERED,
    ]
    here["ann"] = False
    q.tick(101.0, here.__getitem__, False)
    assert q.position("ann") == 2
    assert kinds(q.tick(150.0, here.__getitem__, False)) == []
    # bob's window ran out too: alone in the line, he is offered the arm again
    steps = q.tick(221.0, here.__getitem__, False)
    assert kinds(steps) == [QueueStep.GONE, QueueStep.MISSED, QueueStep.OFFERED]
    assert steps[0].user == "ann" and q.position("ann") is None


def test_the_instructor_reorders_skips_extends_pauses_and_takes_the_arm() -> None:
    q = queue_of("ann", "bob", "cat")
    q.tick(0.0, everyone, False)
    moved = q.move("cat", 1, "ivy")
    assert kinds(moved) == [QueueStep.MOVED] and moved[0].position == 1
    assert [e.user for e in q.entries] == ["cat", "ann", "bob"]
    assert all(e.offered_until is None for e in q.entries)  # the offer is withdrawn
    assert kinds(q.tick(1.0, everyone, False)) == [QueueStep.OFFERED]
    assert q.entries[0].user == "cat"
    assert kinds(q.skip("ann", "ivy", 2.0)) == [QueueStep.SKIPPED]
    q.claim("cat", 3.0)
    assert kinds(q.extend(60, "ivy")) == [QueueStep.EXTENDED]
    assert q.turn is not None and q.turn.ends == 303.0
    taken = q.take("ivy", 103.0)
    assert kinds(taken) == [QueueStep.TAKEN, QueueStep.PAUSED]
    assert q.turn.left_s == 200.0
    assert q.tick(1000.0, everyone, True) == []  # held: cat's time does not run
    resumed = q.resume("ivy", 1000.0)
    assert kinds(resumed) == [QueueStep.RESUMED]
    assert q.turn.ends == 1200.0
    skipped = q.skip("cat", "ivy", 1001.0)
    assert skipped[0].stop and q.turn is None


def test_estimates_follow_cycle_times_and_the_turn_length() -> None:
    q = TurnQueue(SETTINGS)
    q.join(entry("ann", cycle_s=20))
    q.join(entry("bob", cycle_s=None))
    q.join(entry("cat", cycle_s=500))
    assert q.estimates(0.0) == [0.0, 60.0, 300.0]
    q.tick(0.0, everyone, False)
    q.claim("ann", 0.0)
    assert q.estimates(100.0) == [240.0, 480.0]


def test_joining_again_updates_the_text_and_keeps_the_place() -> None:
    q = queue_of("ann", "bob")
    steps = q.join(entry("ann", text="MOV P1"))
    assert kinds(steps) == [QueueStep.UPDATED] and steps[0].position == 1
    assert q.entries[0].program == "MOV P1"


def test_a_workspace_saved_with_another_text_makes_the_entry_stale() -> None:
    q = queue_of("ann")
    assert kinds(q.workspace_saved(7, "MOV P2", "")) == [QueueStep.STALE]
    assert q.entries[0].stale
    assert q.workspace_saved(8, "x", "") == []
    assert kinds(q.workspace_saved(7, "END", "")) == [QueueStep.FRESH]


def test_the_stored_document_gives_the_same_queue() -> None:
    q = queue_of("ann", "bob")
    q.tick(0.0, everyone, False)
    q.claim("ann", 5.0)
    q.set_attended(True, "ivy")
    back = TurnQueue.from_doc(q.to_doc(), SETTINGS)
    assert back == q
