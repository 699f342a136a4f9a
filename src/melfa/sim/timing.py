"""Time along a planned move: the velocity profile of the path parameter s(t) in [0, 1].

`Timing` ramps up, cruises and ramps down (trapezoid or smooth cosine ramps); `StopTiming`
is the constant deceleration of a stop begun mid-move. Pure: times are seconds from a
plan's start.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

__all__ = ["Profile", "StopTiming", "Timing"]


class Profile(enum.Enum):
    """Velocity profile shape in the acceleration and deceleration ramps."""

    TRAPEZOID = "trapezoid"
    SMOOTH = "smooth"
    """Cosine ramps (no step in acceleration); same durations as the trapezoid."""


@dataclass(frozen=True, slots=True)
class Timing:
    """Path parameter s(t) in [0, 1]: ramp up over `t_acc`, cruise, ramp down over `t_dec`.

    `cruise_time` is what the move would take at full rate with infinite acceleration;
    with room to cruise, ``duration = cruise_time + (t_acc + t_dec) / 2``.
    """

    cruise_time: float
    t_acc: float
    t_cruise: float
    t_dec: float
    peak_rate: float
    profile: Profile = Profile.TRAPEZOID

    @classmethod
    def build(
        cls, cruise_time: float, accel_time: float, decel_time: float, profile: Profile
    ) -> Timing:
        if cruise_time <= 0.0:
            return cls(0.0, 0.0, 0.0, 0.0, 0.0, profile)
        vmax = 1.0 / cruise_time
        if (accel_time + decel_time) / 2.0 <= cruise_time:
            t_cruise = cruise_time - (accel_time + decel_time) / 2.0
            return cls(cruise_time, accel_time, t_cruise, decel_time, vmax, profile)
        a, d = vmax / accel_time, vmax / decel_time
        vp = math.sqrt(2.0 / (1.0 / a + 1.0 / d))  # triangular: never reaches vmax
        return cls(cruise_time, vp / a, 0.0, vp / d, vp, profile)

    @property
    def duration(self) -> float:
        return self.t_acc + self.t_cruise + self.t_dec

    def _ramp(self, tau: float, length: float) -> tuple[float, float]:
        """(distance, rate) after `tau` of a ramp from 0 to peak over `length`."""
        vp = self.peak_rate
        if self.profile is Profile.SMOOTH:
            x = math.pi * tau / length
            return vp * (tau / 2.0 - length / (2.0 * math.pi) * math.sin(x)), vp * (
                1.0 - math.cos(x)
            ) / 2.0
        return 0.5 * vp * tau * tau / length, vp * tau / length

    def state(self, t: float) -> tuple[float, float]:
        """(s, ds/dt) at time t, clamped to the plan."""
        if self.duration <= 0.0 or t >= self.duration:
            return 1.0, 0.0
        if t <= 0.0:
            return 0.0, 0.0
        if t < self.t_acc:
            return self._ramp(t, self.t_acc)
        s_acc = 0.5 * self.peak_rate * self.t_acc
        if t < self.t_acc + self.t_cruise:
            return s_acc + self.peak_rate * (t - self.t_acc), self.peak_rate
        rest = self.duration - t
        d, v = self._ramp(rest, self.t_dec)
        return 1.0 - d, v

    def s(self, t: float) -> float:
        return self.state(t)[0]

    @property
    def decel_rate(self) -> float:
        """ds/dt² used for stops (the plan's own deceleration)."""
        return self.peak_rate / self.t_dec if self.t_dec > 0 else math.inf


@dataclass(frozen=True, slots=True)
class StopTiming:
    """Constant deceleration from (s0, v0) to rest."""

    s0: float
    v0: float
    decel: float

    @property
    def duration(self) -> float:
        return self.v0 / self.decel if self.decel < math.inf and self.v0 > 0 else 0.0

    def s(self, t: float) -> float:
        t = min(max(t, 0.0), self.duration)
        return min(1.0, self.s0 + self.v0 * t - 0.5 * self.decel * t * t)
