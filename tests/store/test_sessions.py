"""Sessions (hashed tokens, expiry, revocation, CSRF) and login rate limiting."""

from __future__ import annotations

import sqlite3
from datetime import timedelta
from pathlib import Path

from melfa.store import Store, check_csrf
from melfa.store.sessions import hash_token
from tests.store.conftest import FakeClock


def test_session_token_is_stored_hashed(store: Store, db_path: Path) -> None:
    user = store.accounts.create_user("ada", "kettle-moon-1")
    new = store.sessions.create(user, "10.0.0.7")
    conn = sqlite3.connect(db_path)
    stored = [r[0] for r in conn.execute("SELECT token_hash FROM sessions")]
    conn.close()
    assert stored == [hash_token(new.token)]
    assert new.token not in stored
    assert new.session.id == hash_token(new.token)


def test_lookup_finds_the_user(store: Store) -> None:
    user = store.accounts.create_user("ada", "kettle-moon-1", group="G1")
    new = store.sessions.create(user)
    found = store.sessions.lookup(new.token)
    assert found is not None
    assert found.user.username == "ada"
    assert found.csrf_token == new.session.csrf_token
    assert store.sessions.lookup("not-a-token") is None
    assert store.sessions.lookup(None) is None
    assert store.sessions.lookup("") is None


def test_csrf_token_is_per_session(store: Store) -> None:
    user = store.accounts.create_user("ada", "kettle-moon-1")
    one = store.sessions.create(user).session
    two = store.sessions.create(user).session
    assert one.csrf_token != two.csrf_token
    assert check_csrf(one, one.csrf_token)
    assert not check_csrf(one, two.csrf_token)
    assert not check_csrf(one, None)
    assert not check_csrf(one, "")


def test_session_expires_after_its_lifetime(store: Store, clock: FakeClock) -> None:
    user = store.accounts.create_user("ada", "kettle-moon-1")
    token = store.sessions.create(user).token
    policy = store.sessions.policy
    deadline = clock.now + policy.lifetime
    # Kept busy, so idling never ends it, until just before the absolute lifetime.
    while clock.now + policy.idle_timeout / 2 < deadline:
        clock.advance(seconds=(policy.idle_timeout / 2).total_seconds())
        assert store.sessions.lookup(token) is not None
    clock.now = deadline
    assert store.sessions.lookup(token) is None


def test_session_expires_when_idle(store: Store, clock: FakeClock) -> None:
    user = store.accounts.create_user("ada", "kettle-moon-1")
    token = store.sessions.create(user).token
    idle = store.sessions.policy.idle_timeout
    clock.advance(seconds=(idle - timedelta(minutes=5)).total_seconds())
    assert store.sessions.lookup(token) is not None  # touched: idle time restarts
    clock.advance(seconds=(idle - timedelta(minutes=5)).total_seconds())
    assert store.sessions.lookup(token) is not None
    clock.advance(seconds=idle.total_seconds())
    assert store.sessions.lookup(token) is None


def test_expired_sessions_are_purged(store: Store, clock: FakeClock) -> None:
    user = store.accounts.create_user("ada", "kettle-moon-1")
    store.sessions.create(user)
    clock.advance(hours=1)
    fresh = store.sessions.create(user).token
    clock.advance(
        seconds=(store.sessions.policy.idle_timeout - timedelta(minutes=30)).total_seconds()
    )
    assert store.sessions.purge_expired() == 1
    assert store.sessions.lookup(fresh) is not None


def test_revoke_one_and_all(store: Store) -> None:
    ada = store.accounts.create_user("ada", "kettle-moon-1")
    bob = store.accounts.create_user("bob", "kettle-moon-1")
    a1, a2 = store.sessions.create(ada).token, store.sessions.create(ada).token
    b1 = store.sessions.create(bob).token
    assert store.sessions.revoke(a1)
    assert not store.sessions.revoke(a1)
    assert store.sessions.lookup(a1) is None
    assert store.sessions.lookup(a2) is not None
    assert store.sessions.revoke_all(ada.id) == 1
    assert store.sessions.lookup(a2) is None
    assert store.sessions.lookup(b1) is not None


def test_password_change_disable_and_removal_end_sessions(store: Store) -> None:
    ada = store.accounts.create_user("ada", "kettle-moon-1")
    bob = store.accounts.create_user("bob", "kettle-moon-1")
    cy = store.accounts.create_user("cy", "kettle-moon-1")
    ta, tb, tc = (store.sessions.create(u).token for u in (ada, bob, cy))
    store.accounts.set_password("ada", "kettle-moon-2")
    store.accounts.set_disabled("bob", True)
    store.accounts.remove_user("cy")
    assert [store.sessions.lookup(t) for t in (ta, tb, tc)] == [None, None, None]


def test_rate_limit_per_username_backs_off(store: Store, clock: FakeClock) -> None:
    policy = store.logins.policy
    for _ in range(policy.max_failures_per_user - 1):
        store.logins.record("ada", "10.0.0.1", success=False)
        clock.advance(minutes=1)
    assert store.login_allowed("ada", "10.0.0.1")
    store.logins.record("ADA", "10.0.0.2", success=False)  # any address, any case
    decision = store.login_allowed("ada", "10.0.0.3")
    assert not decision and decision.reason == "too many failed sign-ins for this account"
    assert decision.retry_after == policy.backoff_base  # a wait, not a lock-out
    assert store.login_allowed("bob", "10.0.0.1")  # other users unaffected
    clock.advance(seconds=decision.retry_after.total_seconds())
    assert store.login_allowed("ada", "10.0.0.1")
    store.logins.record("ada", "10.0.0.2", success=False)
    again = store.login_allowed("ada", "10.0.0.3")
    assert again.retry_after == policy.backoff_base * 2  # doubled


def test_rate_limit_per_address(store: Store, clock: FakeClock) -> None:
    limit = store.logins.policy.max_failures_per_addr
    for i in range(limit):
        store.logins.record(f"user{i}", "10.9.9.9", success=False)
    assert not store.login_allowed("fresh", "10.9.9.9")
    assert store.login_allowed("fresh", "10.9.9.10")
    clock.advance(seconds=store.logins.policy.window.total_seconds() + 1)
    assert store.login_allowed("fresh", "10.9.9.9")


def test_success_forgives_earlier_failures(store: Store) -> None:
    for _ in range(store.logins.policy.max_failures_per_user - 1):
        store.logins.record("ada", "10.0.0.1", success=False)
    store.logins.record("ada", "10.0.0.1", success=True)
    store.logins.record("ada", "10.0.0.1", success=False)
    assert store.login_allowed("ada", "10.0.0.1")


def test_an_attacker_elsewhere_does_not_lock_out_the_owner(store: Store) -> None:
    store.logins.record("ada", "10.0.0.1", success=True)  # her usual computer
    for _ in range(50):
        store.logins.begin("ada", "10.6.6.6")  # admitted ones count as failures
    assert not store.login_allowed("ada", "10.6.6.6")
    assert not store.login_allowed("ada", "10.7.7.7")  # the account, from anywhere new
    assert store.login_allowed("ada", "10.0.0.1")  # but not from where she signs in


def test_concurrent_attempts_are_counted_before_the_password(store: Store) -> None:
    from melfa.store.logins import LoginTicket

    admitted = [store.logins.begin("ada", f"10.1.1.{i}") for i in range(100)]
    tickets = [t for t in admitted if isinstance(t, LoginTicket)]
    assert len(tickets) == store.logins.policy.max_failures_per_user
