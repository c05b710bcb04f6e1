"""How an episode ends: one small object per end condition, checked in order every cycle.

Each ending is called with the simulated time (s) and the robot's true position (m) and says
whether the episode ends now; its ``outcome`` names the end. A new end condition is one more
class with ``outcome`` and ``__call__``; which endings an episode has, and their values, is its
protocol's choice (:meth:`nav_bench.episode.protocol.Protocol.endings`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Protocol

import numpy as np

from nav_bench.interface import Outcome


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


class Collided:
    """The robot touched something: ``collisions()`` counts its distinct contacts so far."""

    outcome = Outcome.COLLISION

    def __init__(self, collisions: Callable[[], int]) -> None:
        self.collisions = collisions

    def __call__(self, t: float, xy: np.ndarray) -> bool:
        return self.collisions() > 0


def first_ending(checks: Sequence[Ending], t: float, xy: np.ndarray) -> Outcome | None:
    """The outcome of the first ending that holds, or None: the episode goes on."""
    for check in checks:
        if check(t, xy):
            return check.outcome
    return None
