"""Bug2 on sonars.

Reference: V. J. Lumelsky and A. A. Stepanov, "Path-planning strategies for a point mobile
automaton moving amidst unknown obstacles of arbitrary shape", Algorithmica 2:403-430, 1987.

The m-line is the segment from the start (the pose at :meth:`Bug2.reset`) to the goal.

* **Motion to goal**: turn toward the goal and drive. An echo in the corridor ahead closer
  than ``hit_distance`` is a *hit point* H; the robot starts following the obstacle.
* **Boundary following**: keep the obstacle on ``wall_side`` at ``wall_distance``
  (:class:`~nav_bench.planners.follow.WallFollower`: the tangent of the nearest echo on that
  side, from a short memory of the side sonar's echoes).
* **Leave**: when the robot crosses the m-line (or is within ``mline_tolerance`` of it) at
  a point closer to the goal than H by ``leave_margin``, and the way toward the goal is free
  (no sonar echo of the last ``memory_s`` s in a robot-wide corridor ``leave_clear`` m long),
  it resumes motion to goal.
* **Unreachable**: if it comes back to H (within ``loop_radius``) after a lap round the
  followed boundary (net turn toward ``wall_side``), the goal cannot be reached: it stops and emits an ``unreachable`` event.

Every hit emits a ``replan`` event (the path changes from the m-line to the boundary).
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from nav_bench.interface import Command, Observation
from nav_bench.planners.base import Param, Planner
from nav_bench.planners.follow import (
    FOLLOW,
    GO,
    LEFT,
    RIGHT,
    STOP,
    UNREACHABLE,
    EchoMemory,
    LoopDetector,
    WallFollower,
    arrival_speed,
    corridor_half_width,
    free_along,
    obstacle_ahead,
    steer,
)


class Bug2(Planner):
    """Bug2 (Lumelsky & Stepanov 1987): m-line, sonar wall following, m-line leave rule."""

    name: ClassVar[str] = "bug2"
    reference: ClassVar[str] = ("Lumelsky & Stepanov, Path-planning strategies for a point mobile "
                                "automaton moving amidst unknown obstacles, Algorithmica 1987")
    params: ClassVar[tuple[Param, ...]] = (
        Param("v_max", 0.4, "m/s", "cruise speed (capped by the robot's limit)", minimum=0.0),
        Param("hit_distance", 0.55, "m", "echo this close ahead (from the robot centre) is a hit point",
              minimum=0.0),
        Param("wall_side", "right", "-", "side the obstacle is kept on while following it",
              choices=("left", "right")),
        Param("wall_distance", 0.4, "m", "distance kept from the followed wall (robot centre)",
              minimum=0.0),
        Param("front_distance", 0.45, "m", "while following, turn on the spot if an echo is this close ahead",
              minimum=0.0),
        Param("mline_tolerance", 0.1, "m", "distance from the m-line that counts as being on it",
              minimum=0.0),
        Param("leave_margin", 0.2, "m", "a leave point must be this much closer to the goal than the hit point",
              minimum=0.0),
        Param("leave_clear", 0.4, "m", "free corridor toward the goal required to leave the boundary",
              minimum=0.0),
        Param("memory_s", 6.0, "s", "how long sonar echoes are remembered for the leave check",
              minimum=0.0),
        Param("loop_radius", 0.4, "m", "back within this of the hit point after a lap = goal unreachable",
              minimum=0.0),
    )

    def reset(self, obs: Observation, rng: np.random.Generator) -> None:
        super().reset(obs, rng)
        p = self.settings
        self.start = np.asarray(obs.pose[:2], dtype=float).copy()
        self.goal = np.asarray(obs.goal, dtype=float).copy()
        self.mode = GO
        self.hit: np.ndarray | None = None
        self.hit_goal_distance = math.inf
        self.side = LEFT if p.wall_side == "left" else RIGHT
        self.follower = WallFollower(self.side, p.wall_distance, p.v_max, p.front_distance)
        self.memory = EchoMemory(p.memory_s)
        self.loop = LoopDetector(p.loop_radius, min_length=4 * p.loop_radius, side=self.side)
        self._prev_xy = self.start.copy()
        self._hits: list[list[float]] = []

    # -- m-line geometry -------------------------------------------------------------------------
    def _mline_offset(self, xy: np.ndarray, goal: np.ndarray) -> float:
        """Signed distance (m) of ``xy`` from the m-line's supporting line (+ = left of start->goal)."""
        d = goal - self.start
        n = float(np.hypot(*d))
        if n < 1e-9:
            return 0.0
        # Python floats: the same IEEE operations as on NumPy scalars, at a fraction of the cost
        (dx, dy), (x, y), (x0, y0) = d.tolist(), xy.tolist(), self.start.tolist()
        return (dx * (y - y0) - dy * (x - x0)) / n

    def _on_mline(self, xy: np.ndarray, goal: np.ndarray) -> bool:
        """On the m-line segment now, or crossed it since the last cycle."""
        off, prev = self._mline_offset(xy, goal), self._mline_offset(self._prev_xy, goal)
        d = goal - self.start
        along = float(np.dot(xy - self.start, d) / max(float(np.dot(d, d)), 1e-12))
        within = -0.05 <= along <= 1.05
        return within and (abs(off) <= self.settings.mline_tolerance or off * prev < 0.0)

    # -- control ---------------------------------------------------------------------------------
    def act(self, obs: Observation) -> Command:
        p = self.settings
        xy, goal = np.asarray(obs.pose[:2], dtype=float), np.asarray(obs.goal, dtype=float)
        self.memory.add(obs)
        self.follower.observe(obs)  # remember the boundary before following it
        to_goal = float(np.hypot(*(goal - xy)))
        heading = math.atan2(goal[1] - xy[1], goal[0] - xy[0])
        v = min(p.v_max, obs.robot.v_max)
        half_width = corridor_half_width(obs.robot)
        cmd = STOP
        if self.mode == GO:
            ahead = obstacle_ahead(obs, p.hit_distance, half_width)
            facing = abs(math.remainder(heading - float(obs.pose[2]), 2 * math.pi)) < math.radians(30)
            if ahead < p.hit_distance and facing and ahead < to_goal:
                self.mode, self.hit, self.hit_goal_distance = FOLLOW, xy.copy(), to_goal
                self.loop.arm(xy, float(obs.pose[2]))
                self._hits.append([float(xy[0]), float(xy[1])])
                self.emit("replan", obs.t, reason="hit", x=float(xy[0]), y=float(xy[1]))
            else:
                cmd = steer(obs, heading, arrival_speed(to_goal, v))
        if self.mode == FOLLOW:
            if self.loop.update(xy, float(obs.pose[2])):
                self.mode = UNREACHABLE
                self.emit("unreachable", obs.t, x=float(xy[0]), y=float(xy[1]))
            elif (self._on_mline(xy, goal) and to_goal < self.hit_goal_distance - p.leave_margin
                  and free_along(self.memory.points(xy, p.leave_clear + 1.0), xy, heading,
                                 min(p.leave_clear, to_goal), half_width, body=obs.robot.radius)):
                self.mode = GO
                self.loop.disarm()
                cmd = steer(obs, heading, arrival_speed(to_goal, v))
            else:
                cmd = self.follower.act(obs)
        self._prev_xy = xy.copy()
        return cmd

    def debug_state(self) -> dict[str, Any]:
        """``mode``, ``hit_points`` [[x, y], ...] and ``m_line`` [[start], [goal]] (m)."""
        if not hasattr(self, "start"):
            return {}
        return {"mode": self.mode, "hit_points": [list(h) for h in self._hits],
                "m_line": [self.start.tolist(), self.goal.tolist()]}
