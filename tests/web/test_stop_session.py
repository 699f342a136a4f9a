"""A REST STOP as direct as the WebSocket's (issue 27): its session comes from memory when
this server confirmed it recently, so it waits for no thread — not the store's, not its
own lookup pool's, not the thread pool FastAPI shares among requests — while sign-out and
revocation stay exact for everything else. Through a real uvicorn; nothing is timed:
the threads are held by a latch, and STOP must be answered while they are."""

from __future__ import annotations

import logging
import threading
from collections.abc import Iterator
from pathlib import Path

import anyio.to_thread
import pytest

from melfa.web.known_sessions import KnownSessions
from melfa.web.pools import BoundedPool, PoolSizes
from tests.waiting import wait_until
from tests.web.live_server import Live, fresh_live


@pytest.fixture
def live(tmp_path: Path) -> Iterator[Live]:
    with fresh_live(tmp_path) as server:
        yield server


def auth(token: str, csrf: str) -> dict[str, str]:
    return {"Cookie": f"melfa_session={token}", "X-CSRF-Token": csrf}


def stop(live: Live, headers: dict[str, str]) -> int:
    with live.client() as c:
        return c.post("/api/robot/stop", headers=headers, timeout=30).status_code


class Clock:
    """The known sessions' clock, moved by the test."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def hold(pool: BoundedPool, threads: int, latch: threading.Event, live: Live) -> None:
    """Every one of ``pool``'s ``threads`` waiting on ``latch`` (called on the server's
    loop, as the server calls it); returns once they all wait."""
    waiting = threading.Semaphore(0)

    def wait() -> None:
        waiting.release()
        latch.wait(60)

    async def submit() -> None:
        assert live.loop is not None
        task = live.loop.create_task(pool.run(wait))
        held.append(task)

    held: list[object] = []
    for _ in range(threads):
        live.on_loop(submit())
    for _ in range(threads):
        assert waiting.acquire(timeout=30), "a pool thread did not start"


def test_a_known_sessions_stop_waits_for_no_thread(live: Live) -> None:
    token, csrf = live.login("ivy")
    pools = live.context.pools
    latch = threading.Event()

    async def borrow_the_shared_pool() -> list[object]:
        limiter = anyio.to_thread.current_default_thread_limiter()
        holders = [object() for _ in range(int(limiter.total_tokens))]
        for holder in holders:
            await limiter.acquire_on_behalf_of(holder)
        return holders

    async def give_back(holders: list[object]) -> None:
        limiter = anyio.to_thread.current_default_thread_limiter()
        for holder in holders:
            limiter.release_on_behalf_of(holder)

    holders = live.on_loop(borrow_the_shared_pool())
    try:
        hold(pools.db, PoolSizes().db_workers, latch, live)
        hold(pools.stop, 1, latch, live)
        # Every thread a request could wait for is taken: only a STOP that needs none is
        # answered (before, it waited for the shared pool and then its lookup pool).
        assert stop(live, auth(token, csrf)) == 200
    finally:
        latch.set()
        live.on_loop(give_back(holders))


def test_a_stop_without_the_csrf_token_or_session_is_still_refused(live: Live) -> None:
    token, csrf = live.login("ann")
    assert stop(live, {"Cookie": f"melfa_session={token}"}) == 403
    assert stop(live, auth("not-a-session", csrf)) == 401
    assert stop(live, auth(token, csrf)) == 200


def test_signing_out_and_revocations_here_end_stop_at_once(live: Live) -> None:
    ann, ann_csrf = live.login("ann")
    assert stop(live, auth(ann, ann_csrf)) == 200
    with live.client() as c:
        assert c.delete("/api/session", headers=auth(ann, ann_csrf)).status_code == 200
    assert stop(live, auth(ann, ann_csrf)) == 401

    bob, bob_csrf = live.login("bob")
    ivy, ivy_csrf = live.login("ivy")
    assert stop(live, auth(bob, bob_csrf)) == 200
    with live.client() as c:
        reply = c.put(
            "/api/users/bob/password", json={"password": None}, headers=auth(ivy, ivy_csrf)
        )
        assert reply.status_code == 200, reply.text
    assert stop(live, auth(bob, bob_csrf)) == 401

    cat, cat_csrf = live.login("cat")
    with live.client() as c:
        made = c.post("/api/tokens", json={"label": "arm"}, headers=auth(cat, cat_csrf))
        assert made.status_code == 201, made.text
        pat, number = made.json()["token"], made.json()["info"]["id"]
        bearer = {"Authorization": f"Bearer {pat}"}
        assert c.post("/api/robot/stop", headers=bearer).status_code == 200
        gone = c.delete(f"/api/tokens/{number}", headers=auth(cat, cat_csrf))
        assert gone.status_code == 200, gone.text
        assert c.post("/api/robot/stop", headers=bearer).status_code == 401


def test_a_session_revoked_by_another_process_is_found_on_its_next_read(live: Live) -> None:
    """`melfa users` in another process: every other request is refused at once; a STOP
    may still be answered from memory (stopping the arm harms no one), which reads the
    session again once older than `Limits.socket_recheck_s`; then STOP is refused too."""
    known = live.context.guard.known
    clock = Clock()
    known.clock = clock
    token, csrf = live.login("ann")
    assert stop(live, auth(token, csrf)) == 200  # remembered
    assert live.store.sessions.revoke(token)  # as another process would
    with live.client() as c:
        assert c.get("/api/session", headers=auth(token, csrf)).status_code == 401
    assert stop(live, auth(token, csrf)) == 200  # fresh in memory
    clock.now += known.fresh_s
    assert stop(live, auth(token, csrf)) == 200  # answered, then read again
    wait_until(lambda: known.recall(token) is None, what="the revoked session forgotten")
    assert stop(live, auth(token, csrf)) == 401

    other, other_csrf = live.login("bob")
    assert stop(live, auth(other, other_csrf)) == 200
    live.store.sessions.revoke(other)
    clock.now += known.keep_s  # not confirmed for too long: read before use
    assert stop(live, auth(other, other_csrf)) == 401


def test_a_stop_from_memory_is_audited_with_its_user(live: Live) -> None:
    token, csrf = live.login("bob")
    assert live.context.guard.known.recall(token) is not None  # signing in remembered it
    assert stop(live, auth(token, csrf)) == 200
    wait_until(
        lambda: live.store.audit.query(action="robot.stop", actor="bob").entries,
        what="bob's STOP in the audit log",
    )


def test_known_sessions_keep_the_newest_and_forget_a_user_but_one_session(live: Live) -> None:
    ann = [live.store.sessions.create(live.store.accounts.get_user("ann"), None) for _ in "ab"]
    bob = live.store.sessions.create(live.store.accounts.get_user("bob"), None)
    small = KnownSessions(capacity=2)
    for new in (*ann, bob):
        small.remember(new.token, new.session)
    assert len(small) == 2 and small.recall(ann[0].token) is None  # the oldest went
    known = KnownSessions()
    for new in (*ann, bob):
        known.remember(new.token, new.session)
    known.forget_user("ann", keep_session=ann[0].session.id)
    assert known.recall(ann[0].token) is not None and known.recall(ann[1].token) is None
    assert known.recall(bob.token) is not None


def test_a_re_read_that_cannot_be_made_leaves_the_stop_answered_and_no_error(
    live: Live, caplog: pytest.LogCaptureFixture
) -> None:
    known = live.context.guard.known
    clock = Clock()
    known.clock = clock
    token, csrf = live.login("ann")
    pool = live.context.pools.stop
    pool.shutdown()  # as when the server closes: no read can be made
    tried = pool.done
    clock.now += known.fresh_s
    assert stop(live, auth(token, csrf)) == 200
    wait_until(lambda: pool.done > tried, what="the re-read tried")
    assert known.recall(token) is not None  # kept until it ages out
    assert not [r for r in caplog.records if r.levelno >= logging.ERROR]
