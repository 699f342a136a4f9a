"""Sign in and out, cookies, CSRF, rate limiting, roles, user management."""

from __future__ import annotations

from tests.web.conftest import PASSWORDS, Web, assert_error


def test_login_gives_session_and_csrf(web: Web) -> None:
    response = web.client.post(
        "/api/session", json={"username": "ann", "password": PASSWORDS["ann"]}
    )
    assert response.status_code == 200
    body = response.json()
    assert body["user"]["username"] == "ann" and body["user"]["role"] == "student"
    assert "password" not in str(body).lower().replace("csrf", "")
    cookies = response.headers.get_list("set-cookie")
    session = next(c for c in cookies if c.startswith("melfa_session="))
    assert "HttpOnly" in session and "SameSite=strict" in session and "Secure" not in session
    csrf = next(c for c in cookies if c.startswith("melfa_csrf="))
    assert "HttpOnly" not in csrf and body["csrf_token"] in csrf


def test_cookies_are_secure_over_https(web: Web) -> None:
    response = web.client.post(
        "https://testserver/api/session", json={"username": "ann", "password": PASSWORDS["ann"]}
    )
    assert response.status_code == 200
    assert all("Secure" in c for c in response.headers.get_list("set-cookie"))


def test_wrong_password_and_unknown_user_look_the_same(web: Web) -> None:
    a = web.client.post("/api/session", json={"username": "ann", "password": "not-it-at-all"})
    b = web.client.post("/api/session", json={"username": "nobody", "password": "not-it-at-all"})
    assert assert_error(a, 401, "wrong-login")["message"] == assert_error(b, 401)["message"]


def test_whoami_and_logout(web: Web) -> None:
    ann = web.ann
    assert ann.get("/api/session").json()["user"]["username"] == "ann"
    assert ann.delete("/api/session").json() == {"ok": True}
    assert_error(ann.get("/api/session"), 401, "not-signed-in")
    assert_error(ann.get("/api/workspaces"), 401, "not-signed-in")


def test_csrf_refused_without_or_with_wrong_token(web: Web) -> None:
    ann = web.ann
    without = web.client.post(
        "/api/robot/servo", json={"on": True}, headers=ann.headers(csrf=False)
    )
    assert_error(without, 403, "csrf-token-missing")
    wrong = web.client.delete("/api/session", headers=ann.headers({"X-CSRF-Token": "x" * 43}))
    assert_error(wrong, 403, "csrf-token-missing")
    # another user's token is no good either
    bob = web.bob
    mixed = web.client.post(
        "/api/lease", headers={**ann.headers(csrf=False), "X-CSRF-Token": bob.csrf}
    )
    assert_error(mixed, 403, "csrf-token-missing")
    assert ann.get("/api/session").status_code == 200  # still signed in


def test_login_rate_limited(web: Web) -> None:
    for _ in range(5):
        bad = web.client.post("/api/session", json={"username": "bob", "password": "wrong-guess-1"})
        assert_error(bad, 401, "wrong-login")
    limited = web.client.post(
        "/api/session", json={"username": "bob", "password": PASSWORDS["bob"]}
    )
    error = assert_error(limited, 429, "too-many-logins")
    assert "too many failed sign-ins" in error["message"] and "wait" in error["message"]
    assert int(limited.headers["retry-after"]) > 0
    # other users are not locked out
    assert (
        web.client.post(
            "/api/session", json={"username": "ann", "password": PASSWORDS["ann"]}
        ).status_code
        == 200
    )


def test_login_form_page_and_redirect(web: Web) -> None:
    page = web.client.get("/login")
    assert page.status_code == 200 and '<form method="post" action="/login"' in page.text
    response = web.client.post(
        "/login",
        data={"username": "ann", "password": PASSWORDS["ann"], "next": "/audit"},
        follow_redirects=False,
    )
    assert response.status_code == 303 and response.headers["location"] == "/audit"
    assert "melfa_session" in response.cookies
    web.client.cookies.clear()
    evil = web.client.post(
        "/login",
        data={"username": "ann", "password": PASSWORDS["ann"], "next": "//evil.example/"},
        follow_redirects=False,
    )
    assert evil.headers["location"] == "/"
    web.client.cookies.clear()
    wrong = web.client.post("/login", data={"username": "ann", "password": "nope-nope-nope"})
    assert wrong.status_code == 401 and "Wrong username or password" in wrong.text


def test_login_from_another_site_refused(web: Web) -> None:
    response = web.client.post(
        "/api/session",
        json={"username": "ann", "password": PASSWORDS["ann"]},
        headers={"origin": "http://evil.example"},
    )
    assert_error(response, 403, "bad-origin")


def test_index_needs_login(web: Web) -> None:
    assert web.client.get("/", follow_redirects=False).headers["location"] == "/login"
    assert web.ann.get("/").status_code == 200


def test_student_cannot_manage_users(web: Web) -> None:
    ann = web.ann
    assert_error(ann.get("/api/users"), 403, "forbidden")
    assert_error(
        ann.post("/api/users", json={"username": "eve", "role": "admin"}), 403, "forbidden"
    )
    assert_error(ann.delete("/api/users/bob"), 403, "forbidden")
    assert_error(ann.put("/api/users/bob/password", json={}), 403, "forbidden")


def test_admin_manages_users(web: Web) -> None:
    admin = web.admin
    names = [u["username"] for u in admin.get("/api/users").json()["users"]]
    assert names == ["admin", "ann", "bob", "cat", "ivy"]
    created = admin.post("/api/users", json={"username": "Dan", "group": "G3"})
    assert created.status_code == 201
    password = created.json()["password"]
    assert created.json()["user"] == {**created.json()["user"], "username": "dan", "group": "G3"}
    assert (
        web.client.post("/api/session", json={"username": "dan", "password": password}).status_code
        == 200
    )
    web.client.cookies.clear()
    assert_error(admin.post("/api/users", json={"username": "dan"}), 409, "already-exists")
    assert_error(
        admin.post("/api/users", json={"username": "x", "password": "short"}),
        422,
        "invalid-value",
    )
    new = admin.put("/api/users/dan/password", json={"password": "another-password"})
    assert new.json() == {"password": None}
    assert admin.delete("/api/users/dan").json() == {"ok": True}
    assert_error(admin.delete("/api/users/dan"), 404, "not-found")
    assert_error(admin.delete("/api/users/admin"), 409)
