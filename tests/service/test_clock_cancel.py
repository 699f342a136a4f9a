"""A `FakeClock`'s driver stops when cancelled, even in the turn a clock thread wakes it.

Python 3.11's ``asyncio.wait_for`` returned the wake-up instead and dropped the
cancellation: the driver then slept on for good, and the test that ended its clock
(``async with clock.running()``) waited for it forever."""

from __future__ import annotations

import asyncio

from melfa.service.clock import FakeClock


def test_a_cancel_that_meets_a_wake_up_still_stops_the_driver() -> None:
    async def main() -> None:
        clock = FakeClock()
        driver = asyncio.create_task(clock.run())
        with clock.thread():  # a clock thread at work: the driver waits for it to wait
            for _ in range(8):
                await asyncio.sleep(0)
            assert not driver.done()
        await asyncio.sleep(0)  # the thread's end wakes the driver in this turn...
        driver.cancel()  # ...and the test ends the clock in the same one
        for _ in range(8):
            await asyncio.sleep(0)
        assert driver.cancelled()

    asyncio.run(main())
