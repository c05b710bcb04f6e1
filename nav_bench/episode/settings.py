"""How an episode is played: rates, limits and tolerances, each with its default in one place."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

from nav_bench.episode.ending import DEFAULT_AREA_RADIUS
from nav_bench.errors import InputError
from nav_bench.specs import GOAL_TOLERANCE_M, WorldSpec


@dataclass(frozen=True)
class EpisodeSettings:
    """How an episode is played. Times in s, distances in m, rates in Hz."""

    control_hz: float = 10.0  # planner cycles per second (the paper's control cycle)
    # physics steps per second; the same value as nav_bench.sim.session.PHYSICS_HZ (why 60:
    # results/fidelity/README.md). A suite plays the 240 Hz reference with limits: {physics_hz: 240}
    physics_hz: float = 60.0
    time_s: float | None = None  # simulated time limit; None: 15 s per metre of (sx + sy), >= 60 s
    stuck_s: float | None = 30.0  # "stuck" if the robot stays within stuck_radius this long; None: off
    stuck_radius: float = 0.2  # m
    # m, also "stuck" when the positions of the last 3 x stuck_s fit in a disc this size (an
    # oscillating robot; nav_bench.episode.ending.Stuck, which says why 0.6); None: off
    stuck_area_radius: float | None = DEFAULT_AREA_RADIUS
    # m, true distance to the goal that counts as reached. Planners stop at their own tolerance
    # (0.2 m by default) judged on odometry; the extra 0.1 m absorbs odometry drift, so success
    # measures navigation and a default-noise robot that stopped "at" the goal is not "stuck".
    goal_tolerance: float = GOAL_TOLERANCE_M
    record_trace: bool = True  # keep per-cycle arrays (needed for plots and traces on disk)
    # m, edge-to-geometry distance under which the row's time_near_obstacles_s counts (MRPB's
    # safety distance)
    safety_distance_m: float = 0.3
    # the rules the episode is judged by (nav_bench.episode.protocol): a name and its settings
    protocol: str = "nav_bench"
    protocol_options: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name in ("control_hz", "physics_hz", "time_s", "stuck_s", "stuck_radius",
                     "goal_tolerance", "safety_distance_m"):
            value = getattr(self, name)
            if value is not None and not math.isfinite(value):
                raise InputError(f"{name} must be a finite number, got {value}")
        if self.control_hz <= 0 or self.physics_hz <= 0:
            raise InputError("control_hz and physics_hz must be positive")
        if self.physics_hz < self.control_hz:
            raise InputError("physics_hz must be at least control_hz")
        if self.time_s is not None and self.time_s <= 0:
            raise InputError("time_s must be positive")
        if self.goal_tolerance <= 0:
            raise InputError("goal_tolerance must be positive")
        if self.safety_distance_m < 0:
            raise InputError("safety_distance_m must not be negative")
        from nav_bench.episode.protocol import make_protocol  # it builds on these settings

        make_protocol(self.protocol, self.protocol_options)  # unknown names and settings fail here

    def time_limit(self, world: WorldSpec) -> float:
        """The time limit (s) for ``world``."""
        if self.time_s is not None:
            return float(self.time_s)
        return max(60.0, 15.0 * (world.size[0] + world.size[1]))

    @cached_property  # read every cycle; the settings are frozen
    def steps_per_cycle(self) -> int:
        """Physics steps per control cycle."""
        return max(1, round(self.physics_hz / self.control_hz))

    @cached_property
    def cycle_s(self) -> float:
        """Simulated seconds per control cycle (whole physics steps)."""
        return self.steps_per_cycle / self.physics_hz
