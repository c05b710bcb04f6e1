"""goal_seek: turn toward the goal, drive, slow down and stop before obstacles.

The simplest planner that exercises the control loop end to end: no map, no memory.
It uses the same speed rule as the paper's EO behaviour (:func:`~nav_bench.planners.eopc.eo_speed`)
on the front sonars, and never tries to get around anything: in front of a wall between
it and the goal it stops and stays. It is a baseline, not a solver of traps.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from nav_bench.interface import Command, Observation, wrap_angle
from nav_bench.planners.base import Param, ParamError, Planner
from nav_bench.planners.eopc import FrontSonars, eo_speed, front_sonars, steer


class GoalSeek(Planner):
    """Head straight for the goal; EO-style speed ramp on the front sonars; stop at the goal."""

    name = "goal_seek"
    reference = "baseline: straight to the goal with the paper's EO speed rule"
    params = (
        Param("v_max", 0.5, "m/s", "top translation speed (the robot's own limit also applies)", minimum=0.0),
        Param("v_min", 0.05, "m/s", "floor of the slow-down ramp, so the robot actually reaches "
              "stop_distance instead of creeping toward it", minimum=0.0),
        Param("omega_max", 1.0, "rad/s", "turn-rate limit (the robot's own limit also applies)", minimum=0.0),
        Param("k_heading", 2.0, "1/s", "proportional gain from heading error to turn rate", minimum=0.0),
        Param("align_deg", 60.0, "deg", "heading errors above this are turned in place first; below, "
              "v is scaled by cos(error)", minimum=0.0, maximum=180.0),
        Param("front_fov_deg", 100.0, "deg", "sonars with |mount angle| <= front_fov/2 see 'ahead'",
              minimum=0.0, maximum=360.0),
        Param("slow_distance", 0.8, "m", "start slowing below this front distance (from the robot centre)",
              minimum=0.0),
        Param("stop_distance", 0.35, "m", "stop below this front distance (from the robot centre)",
              minimum=0.0),
        Param("goal_tolerance", 0.2, "m", "stop within this distance of the goal", minimum=0.0),
    )

    @classmethod
    def check_rules(cls, p: dict[str, Any]) -> None:
        if p["slow_distance"] <= p["stop_distance"]:
            raise ParamError("goal_seek needs slow_distance > stop_distance, got "
                             f"{p['slow_distance']} and {p['stop_distance']}", "slow_distance")

    def reset(self, obs: Observation, rng: np.random.Generator) -> None:
        super().reset(obs, rng)
        p = self.settings
        self._front = FrontSonars.of(obs.robot.sonar, front_sonars(obs.robot.sonar, math.radians(p.front_fov_deg)))
        self._v_max = min(p.v_max, obs.robot.v_max)
        self._omega_max = min(p.omega_max, obs.robot.omega_max)
        self._mode = "goal"

    def act(self, obs: Observation) -> Command:
        p = self.settings
        pose = obs.pose
        x, y, yaw = float(pose[0]), float(pose[1]), float(pose[2])
        gx, gy = float(obs.goal[0]), float(obs.goal[1])
        if math.hypot(gx - x, gy - y) < p.goal_tolerance:
            self._mode = "reached"
            return Command(0.0, 0.0)
        error = wrap_angle(math.atan2(gy - y, gx - x) - yaw)
        omega = steer(error, p.k_heading, self._omega_max)
        if abs(error) > math.radians(p.align_deg):
            self._mode = "turn"
            return Command(0.0, omega)
        d = self._front.distance(np.asarray(obs.ranges, dtype=float))
        v = eo_speed(d, self._v_max, p.slow_distance, p.stop_distance, p.v_min)
        self._mode = "goal" if v > 0 else "stopped"
        return Command(v * math.cos(error), omega)

    def debug_state(self) -> dict[str, object]:
        return {"mode": getattr(self, "_mode", "goal")}
