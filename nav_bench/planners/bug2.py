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
  followed boundary (net turn toward ``wall_side``) and that closed lap encloses the goal, the
  goal cannot be reached: it stops and emits an ``unreachable`` event. This is Lumelsky and
  Stepanov's test read as its proof reads it: the robot returns to H without a leave point only
  if the goal is trapped inside the closed curve it followed.
* **A lap that does not enclose the goal** proves nothing: the boundary it followed was not the
  one that blocks the m-line at H (a closed curve round that one, with the goal outside,
  crosses the segment from H to the goal, where the robot would have left). The follower keeps
  the *nearest* echo on its side, so a hit diagonally on a wall with a pillar beside it laps the
  pillar (``very_complex`` seeds 1 and 3: results/baselines/bug2_s13/README.md). The robot then
  emits a ``lap`` event, resumes motion to goal, and at its next hit first turns on the spot
  away from ``wall_side`` until the corridor ahead is clear (at most 135 deg), so that the
  obstacle hit is the one on its side when following starts.

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

# re-acquiring the hit obstacle after a lap round another one: the turn on the spot that brings
# the obstacle ahead to the followed side ends after this much turning even if the corridor
# ahead is still not clear (a pocket), and the follower's own turning takes over from there
TURN_IN_MAX_RAD = 0.75 * math.pi
TURN_IN_RATE = 1.0  # rad/s (at most the robot's limit)


def swept_angle(a: np.ndarray, b: np.ndarray, centre: np.ndarray) -> float:
    """Angle (rad, counter-clockwise positive, in [-pi, pi]) that the straight move from ``a``
    to ``b`` (m) sweeps as seen from ``centre`` (m). Summed over a closed path it is 2 pi times
    the path's winding number round ``centre`` (moves of one control cycle, a few cm, never
    sweep pi unless they pass through ``centre``)."""
    (ax, ay), (bx, by), (cx, cy) = a.tolist(), b.tolist(), centre.tolist()
    return math.remainder(math.atan2(by - cy, bx - cx) - math.atan2(ay - cy, ax - cx), 2 * math.pi)


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
        self._swept = 0.0  # angle (rad) the path since the hit point swept round the goal
        self._reacquire = False  # a lap left the goal outside: turn the next hit obstacle to the side
        self._turn_in: float | None = None  # heading (rad) at that hit while turning it to the side

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
        if self.mode == FOLLOW:  # before a hit in this cycle: the lap's path starts at the hit point
            self._swept += swept_angle(self._prev_xy, xy, goal)
        if self.mode == GO:
            ahead = obstacle_ahead(obs, p.hit_distance, half_width)
            facing = abs(math.remainder(heading - float(obs.pose[2]), 2 * math.pi)) < math.radians(30)
            if ahead < p.hit_distance and facing and ahead < to_goal:
                self.mode, self.hit, self.hit_goal_distance = FOLLOW, xy.copy(), to_goal
                self.loop.arm(xy, float(obs.pose[2]))
                self._swept = 0.0
                if self._reacquire:
                    self._reacquire, self._turn_in = False, float(obs.pose[2])
                self._hits.append([float(xy[0]), float(xy[1])])
                self.emit("replan", obs.t, reason="hit", x=float(xy[0]), y=float(xy[1]))
            else:
                cmd = steer(obs, heading, arrival_speed(to_goal, v))
        if self.mode == FOLLOW:
            if self.loop.update(xy, float(obs.pose[2])):
                cmd = self._lap_closed(obs, xy, goal, heading, v, to_goal)
            elif self._turn_in is not None and (turn := self._turn_to_side(obs, half_width)) is not None:
                cmd = turn
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

    def _lap_closed(self, obs: Observation, xy: np.ndarray, goal: np.ndarray, heading: float,
                    v: float, to_goal: float) -> Command:
        """The robot is back at the hit point after a lap: ``unreachable`` (and stop) if the closed
        lap encloses the goal, else a ``lap`` event and motion to goal, re-acquiring the obstacle
        at the next hit (see the module docstring)."""
        assert self.hit is not None
        winding = round((self._swept + swept_angle(xy, self.hit, goal)) / (2 * math.pi))
        if winding != 0:
            self.mode = UNREACHABLE
            self.emit("unreachable", obs.t, x=float(xy[0]), y=float(xy[1]))
            return STOP
        self.emit("lap", obs.t, x=float(xy[0]), y=float(xy[1]), goal_enclosed=False)
        self.mode, self._reacquire, self._turn_in = GO, True, None
        self.loop.disarm()
        return steer(obs, heading, arrival_speed(to_goal, v))

    def _turn_to_side(self, obs: Observation, half_width: float) -> Command | None:
        """After re-acquiring, the turn on the spot that brings the hit obstacle from ahead to
        the followed side; ``None`` (and no more turning) once the corridor ahead is clear or
        after ``TURN_IN_MAX_RAD``."""
        assert self._turn_in is not None
        turned = abs(math.remainder(float(obs.pose[2]) - self._turn_in, 2 * math.pi))
        if (obstacle_ahead(obs, self.settings.hit_distance, half_width) >= self.settings.hit_distance
                or turned >= TURN_IN_MAX_RAD):
            self._turn_in = None
            return None
        return Command(0.0, -self.side * min(TURN_IN_RATE, obs.robot.omega_max))

    def debug_state(self) -> dict[str, Any]:
        """``mode``, ``hit_points`` [[x, y], ...] and ``m_line`` [[start], [goal]] (m)."""
        if not hasattr(self, "start"):
            return {}
        return {"mode": self.mode, "hit_points": [list(h) for h in self._hits],
                "m_line": [self.start.tolist(), self.goal.tolist()]}
