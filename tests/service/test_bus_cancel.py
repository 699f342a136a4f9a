"""A subscription's reader is cancelled even when its event arrives in the same moment.

Python 3.11's ``asyncio.wait_for`` returns the event instead and drops the cancellation;
a socket's pump, which gets a snapshot 20 times a second, then ran on after its socket had
closed, and `melfa serve` waited out its 3 s graceful shutdown for it on Ctrl-C."""

from __future__ import annotations

import asyncio

import pytest

from melfa.service.bus import EventBus
from melfa.service.events import LinkStatusChanged, StateSnapshot
from melfa.vocab.link import LinkStatus


async def _blocked_reader(seconds: float | None) -> tuple[EventBus, asyncio.Task[object]]:
    bus = EventBus()
    sub = bus.subscribe()
    reader = asyncio.create_task(sub.get_within(seconds))
    for _ in range(3):
        await asyncio.sleep(0)  # the reader waits for an event
    assert not reader.done()
    return bus, reader


@pytest.mark.parametrize("seconds", [None, 30.0])
def test_a_cancel_that_meets_an_event_still_cancels(seconds: float | None) -> None:
    async def main() -> None:
        bus, reader = await _blocked_reader(seconds)
        bus.publish(StateSnapshot())  # the event wakes the reader...
        reader.cancel()  # ...in the very step its socket closes
        with pytest.raises(asyncio.CancelledError):
            await reader

    asyncio.run(main())


def test_an_event_comes_back_and_silence_is_none() -> None:
    async def main() -> None:
        bus, reader = await _blocked_reader(30.0)
        event = LinkStatusChanged(status=LinkStatus.CONNECTED)
        bus.publish(event)
        assert await reader is event
        quiet = bus.subscribe()
        assert await quiet.get_within(0.0) is None  # nothing came: None, no exception

    asyncio.run(main())
