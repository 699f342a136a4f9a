"""`melfa users token|tokens|revoke-token` against a real database file."""

from __future__ import annotations

from pathlib import Path

from tests.cli.test_users import cheap_hashes, data, users

__all__ = ["cheap_hashes", "data"]


def test_a_token_is_printed_once_listed_without_itself_and_revoked(data: Path) -> None:
    assert users(data, "add", "ann", "--generate")[0] == 0
    code, out, err = users(data, "token", "ann", "--label", "thesis page")
    assert code == 0, err
    token = out.strip()
    assert token.startswith("melfa_pat_") and len(token) > 40
    assert "shown only now" in err

    code, out, _ = users(data, "tokens", "ann")
    assert code == 0 and "thesis page" in out and "never" in out
    assert token not in out

    from melfa.store import Store

    with Store.open_dir(data) as store:
        session = store.tokens.lookup(token)
        assert session is not None and session.user.username == "ann"

    code, _, err = users(data, "revoke-token", "ann", "1")
    assert code == 0 and "revoked token 1" in err
    with Store.open_dir(data) as store:
        assert store.tokens.lookup(token) is None
    code, _, err = users(data, "revoke-token", "ann", "1")
    assert code == 1 and "no token number 1" in err
    assert "Traceback" not in err


def test_a_token_for_nobody_is_a_clear_error(data: Path) -> None:
    users(data, "add", "ann", "--generate")
    code, out, err = users(data, "token", "zed")
    assert code == 1 and out == "" and "zed" in err
