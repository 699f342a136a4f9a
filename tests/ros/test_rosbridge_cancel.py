"""A rosbridge socket waiting for its ``auth`` op ends when cancelled (the server shutting
down), even in the turn the op arrives: Python 3.11's ``asyncio.wait_for`` returned the
message instead and dropped the cancellation, and the socket went on to sign in and be
served. The socket is Starlette's own on an in-memory ASGI channel
(`tests.web.asgi_channel`: the race is one turn of the event loop)."""

from __future__ import annotations

import asyncio
from typing import Any, NoReturn

from melfa.ros.rosbridge_server import _Endpoint
from melfa.service.thesis import MELFA
from tests.web.asgi_channel import AsgiChannel, turns


def _unused(*_: Any) -> NoReturn:
    raise AssertionError("a cancelled sign-in goes no further")


def test_a_sign_in_cancelled_as_its_auth_op_comes_in_ends() -> None:
    async def main() -> None:
        endpoint: _Endpoint[Any] = _Endpoint(
            _unused,
            _unused,
            _unused,
            cookie_name="melfa_session",
            allowed_origins=(),
            options={},
            mode=MELFA,
            auth_timeout_s=10.0,
            recheck_s=60.0,
        )
        channel = AsgiChannel()
        signing_in = asyncio.create_task(endpoint._from_auth_op(await channel.accepted()))
        await turns()
        channel.arrives(op="auth", mac="a-token")  # the op...
        signing_in.cancel()  # ...in the very turn the server shuts down
        await turns()
        assert signing_in.cancelled()

    asyncio.run(main())
