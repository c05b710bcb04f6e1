"""Artificial potential field on sonar returns.

Reference: O. Khatib, "Real-time obstacle avoidance for manipulators and mobile robots",
The International Journal of Robotics Research 5(1):90-98, 1986.

The force on the robot is the negative gradient of an attractive goal potential plus a
repulsive potential per sonar echo:

* attraction ``F_att = k_att (goal - x)`` within ``attract_radius`` of the goal (quadratic
  potential) and ``k_att * attract_radius`` toward the goal beyond it (conic potential,
  continuous at the switch);
* repulsion from an echo at clearance ``rho`` (distance from the robot's edge, m) inside
  the influence distance ``rho0``:
  ``F_rep = k_rep (1/rho - 1/rho0) / rho^2`` along ``x - echo``
  (Khatib's FIRAS potential ``0.5 k_rep (1/rho - 1/rho0)^2``); ``rho`` is floored at
  ``min_clearance`` to keep the force finite.

The robot turns toward the force and drives at ``k_v |F|`` (up to ``v_max``), scaled by
the cosine of the heading error (zero beyond ``turn_in_place_deg``).

Local minima are intrinsic to the method: in a U-shaped obstacle open toward the robot
with the goal behind it, the attraction and the repulsion balance inside the U and the
robot stays there. There is deliberately no escape rule; deciding that an episode is
stuck is the episode's job. A reactive method: it emits no ``replan`` events.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from nav_bench.interface import Command, Observation
from nav_bench.planners.base import Param, Planner
from nav_bench.planners.follow import echo_mask, limit, steer


def attractive_force(xy: np.ndarray, goal: np.ndarray, k_att: float, attract_radius: float) -> np.ndarray:
    """(2,) attraction toward ``goal``: quadratic potential within ``attract_radius``, conic beyond."""
    d = np.asarray(goal, dtype=float) - xy
    dist = float(np.hypot(d[0], d[1]))
    if dist <= attract_radius:
        return k_att * d
    return k_att * attract_radius * d / dist


def repulsive_force(xy: np.ndarray, echoes: np.ndarray, robot_radius: float, k_rep: float,
                    rho0: float, min_clearance: float) -> np.ndarray:
    """(2,) sum of FIRAS repulsions of the echo points (M, 2) within ``rho0`` of the robot's edge."""
    if len(echoes) == 0:
        return np.zeros(2)
    away = xy - echoes
    dist = np.maximum(np.hypot(away[:, 0], away[:, 1]), 1e-9)
    rho = np.maximum(dist - robot_radius, min_clearance)
    inside = rho < rho0
    mag = np.where(inside, k_rep * (1.0 / rho - 1.0 / rho0) / rho ** 2, 0.0)
    away *= mag[:, None]
    away /= dist[:, None]
    return np.add.reduce(away, axis=0)  # row by row in echo order, as .sum(axis=0)


class PotentialField(Planner):
    """Artificial potential field (Khatib 1986) with sonar echoes as repulsive points."""

    name: ClassVar[str] = "apf"
    reference: ClassVar[str] = ("Khatib, Real-time obstacle avoidance for manipulators and mobile "
                                "robots, IJRR 5(1), 1986")
    params: ClassVar[tuple[Param, ...]] = (
        Param("v_max", 0.4, "m/s", "top speed (capped by the robot's limit)", minimum=0.0),
        Param("k_att", 1.0, "1/s^2", "attractive gain (force per metre to the goal)", minimum=0.0),
        Param("attract_radius", 1.0, "m", "quadratic attraction within this goal distance, conic beyond",
              minimum=1e-3),
        Param("k_rep", 0.05, "m^2/s^2", "repulsive gain of an echo", minimum=0.0),
        Param("rho0", 0.8, "m", "influence distance of an echo, from the robot's edge", minimum=1e-3),
        Param("min_clearance", 0.05, "m", "clearance floor in the repulsion (keeps the force finite)",
              minimum=1e-4),
        Param("k_v", 0.5, "s", "forward speed per unit of force magnitude", minimum=0.0),
        Param("turn_in_place_deg", 60.0, "deg", "turn on the spot when the force is farther off the heading",
              minimum=0.0, maximum=180.0),
    )

    def reset(self, obs: Observation, rng: np.random.Generator) -> None:
        super().reset(obs, rng)
        self.force = np.zeros(2)

    def forces(self, obs: Observation) -> tuple[np.ndarray, np.ndarray]:
        """(attractive, repulsive) forces (2,) each, world frame, at this observation."""
        p = self.settings
        xy = np.asarray(obs.pose[:2], dtype=float)
        f_att = attractive_force(xy, obs.goal, p.k_att, p.attract_radius)
        echoes = obs.sonar_hits()[echo_mask(obs)]
        f_rep = repulsive_force(xy, echoes, obs.robot.radius, p.k_rep, p.rho0, p.min_clearance)
        return f_att, f_rep

    def act(self, obs: Observation) -> Command:
        p = self.settings
        f_att, f_rep = self.forces(obs)
        self.force = f_att + f_rep
        mag = float(np.hypot(self.force[0], self.force[1]))
        if mag < 1e-9:
            return limit(0.0, 0.0, obs.robot)
        v = min(p.v_max, obs.robot.v_max, p.k_v * mag)
        return steer(obs, math.atan2(self.force[1], self.force[0]), v,
                     turn_in_place=math.radians(p.turn_in_place_deg))

    def debug_state(self) -> dict[str, Any]:
        """``force``: the last total force [fx, fy] (world frame)."""
        return {"force": getattr(self, "force", np.zeros(2)).tolist()}
