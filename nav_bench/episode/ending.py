"""How an episode ends: one small object per end condition, checked in order every cycle.

Each ending is called with the simulated time (s) and the robot's true position (m) and says
whether the episode ends now; its ``outcome`` names the end. A new end condition is one more
class with ``outcome`` and ``__call__``, added to :func:`endings`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np

from nav_bench.episode.settings import EpisodeSettings
from nav_bench.interface import Outcome
from nav_bench.specs import WorldSpec


class Ending(Protocol):
    outcome: Outcome

    def __call__(self, t: float, xy: np.ndarray) -> bool: ...


class GoalReached:
    """The true position is within ``tolerance`` (m) of the goal."""

    outcome = Outcome.REACHED

    def __init__(self, goal: np.ndarray, tolerance: float) -> None:
        self.goal, self.tolerance = goal, tolerance

    def __call__(self, t: float, xy: np.ndarray) -> bool:
        return bool(np.hypot(*(xy - self.goal)) < self.tolerance)


class TimeLimit:
    """The simulated time reached ``limit_s``."""

    outcome = Outcome.TIMEOUT

    def __init__(self, limit_s: float) -> None:
        self.limit_s = limit_s

    def __call__(self, t: float, xy: np.ndarray) -> bool:
        return t >= self.limit_s - 1e-9


class Stuck:
    """The robot stayed within ``radius`` (m) of one point for ``seconds``."""

    outcome = Outcome.STUCK

    def __init__(self, seconds: float, radius: float, start_xy: np.ndarray) -> None:
        self.seconds, self.radius = seconds, radius
        self.anchor, self.since = np.array(start_xy, dtype=float), 0.0

    def __call__(self, t: float, xy: np.ndarray) -> bool:
        if np.hypot(*(xy - self.anchor)) > self.radius:
            self.anchor, self.since = xy.copy(), t
            return False
        return t - self.since >= self.seconds


def endings(settings: EpisodeSettings, world: WorldSpec, start_xy: np.ndarray) -> list[Ending]:
    """The end conditions of an episode of ``world``, in the order they are checked."""
    out: list[Ending] = [GoalReached(np.asarray(world.goal, dtype=float), settings.goal_tolerance),
                         TimeLimit(settings.time_limit(world))]
    if settings.stuck_s is not None:
        out.append(Stuck(settings.stuck_s, settings.stuck_radius, start_xy))
    return out


def first_ending(checks: Sequence[Ending], t: float, xy: np.ndarray) -> Outcome | None:
    """The outcome of the first ending that holds, or None: the episode goes on."""
    for check in checks:
        if check(t, xy):
            return check.outcome
    return None
