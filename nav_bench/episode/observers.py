"""Who watches an episode: the trace recorder, the PyBullet GUI, a live view. One protocol.

The loop hands every observer each control cycle (:class:`Cycle`) before the command is
applied, and closes them when the episode ends. Observers only look: none of them changes
what the robot does.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from nav_bench.interface import RISK_COLORS, Command, Observation, ReplanEvent
from nav_bench.planners.base import Planner


@dataclass
class Cycle:
    """One control cycle as the loop saw it: simulated time ``t`` (s), the true pose, what the
    planner observed and commanded, the events it emitted this cycle, the planner itself and
    the simulation (for drawing and mover positions)."""

    t: float
    true_pose: np.ndarray
    obs: Observation
    cmd: Command
    events: list[dict[str, Any]]
    planner: Planner
    sim: Any


class Observer(Protocol):
    def on_cycle(self, cycle: Cycle) -> None: ...

    def close(self) -> None: ...


class LiveFeed:
    """Feeds a live view (``update(t, pose, state, events)`` and ``close()``, such as
    :class:`nav_bench.reporting.live.LiveView`) every cycle."""

    def __init__(self, view: Any) -> None:
        self.view = view

    def on_cycle(self, cycle: Cycle) -> None:
        self.view.update(cycle.t, cycle.true_pose, cycle.planner.debug_state(), cycle.events)

    def close(self) -> None:
        self.view.close()


def rgb(hex_colour: str) -> tuple[float, float, float]:
    """``#rrggbb`` as PyBullet's (r, g, b) in 0..1."""
    return tuple(int(hex_colour[i:i + 2], 16) / 255 for i in (1, 3, 5))  # type: ignore[return-value]


class GuiView:
    """Draws into the PyBullet GUI (sonar rays, the planner's aim, its last re-plan) and paces
    the episode at real time: each cycle starts ``cycle_s`` of wall time after the last."""

    def __init__(self, cycle_s: float) -> None:
        self.cycle_s = cycle_s
        self._due = 0.0

    def on_cycle(self, cycle: Cycle) -> None:
        time.sleep(max(0.0, self._due - time.perf_counter()))
        self._due = time.perf_counter() + self.cycle_s
        sim, obs = cycle.sim, cycle.obs
        x, y = obs.pose[0], obs.pose[1]
        sim.draw_lines([((x, y), tuple(h)) for h in obs.sonar_hits()], color=(0.1, 0.6, 1.0),
                       key="sonar")
        target = cycle.planner.debug_state().get("target")
        if target is not None:
            sim.draw_lines([((x, y), tuple(target)), (tuple(target), tuple(obs.goal))],
                           color=(1.0, 0.5, 0.0), key="path")
        for plan in filter(None, map(ReplanEvent.from_event, cycle.events)):
            segs = [(plan.breakpoint, n) for n in plan.neighbours]
            risks = plan.risk or (100,) * len(segs)
            for r, colour in RISK_COLORS.items():
                sel = [s for s, ri in zip(segs, risks, strict=False) if ri == r]
                sim.draw_lines(sel, color=rgb(colour), key=f"neighbours{r}")

    def close(self) -> None:
        pass
