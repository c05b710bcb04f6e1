"""Planners that misbehave, for the runner's tests (``tests.helpers.bad_planners:Raises``)."""

from __future__ import annotations

import time

from nav_bench.interface import Command, Observation
from nav_bench.planners.base import Param, Planner


class Raises(Planner):
    """Raises from ``act`` after ``after`` cycles."""

    name = "raises"
    params = (Param("after", 3, "cycles", "cycles played before raising", minimum=0),)

    def reset(self, obs: Observation, rng) -> None:
        super().reset(obs, rng)
        self._cycles = 0

    def act(self, obs: Observation) -> Command:
        self._cycles += 1
        if self._cycles > self.p["after"]:
            raise RuntimeError("planner failure on purpose")
        return Command(0.1, 0.0)


class Hangs(Planner):
    """Never returns from ``act`` (sleeps in a loop, as a planner stuck in a search would)."""

    name = "hangs"
    params = (Param("after", 3, "cycles", "cycles played before hanging", minimum=0),)

    def reset(self, obs: Observation, rng) -> None:
        super().reset(obs, rng)
        self._cycles = 0

    def act(self, obs: Observation) -> Command:
        self._cycles += 1
        while self._cycles > self.p["after"]:
            time.sleep(0.05)
        return Command(0.1, 0.0)
