"""TangentBug with the sonar range as its sensing range.

Reference: I. Kamon, E. Rivlin and E. Rimon, "TangentBug: A range-sensor-based navigation
algorithm", The International Journal of Robotics Research 17(9):934-953, 1998.

TangentBug assumes a 360 deg range sensor that shows the visible boundary of obstacles
within range ``R``. Six sonars sample only six narrow cones, so the *local range
function* is built from a short memory (:class:`~nav_bench.planners.follow.EchoMemory`) of
the echoes of the last ``memory_s`` seconds in the world frame (from the odometry pose):
each echo within ``R`` at distance ``d`` blocks the directions within
``asin((radius + clearance) / d)`` of its bearing (the obstacle grown by the robot), and
``rho(theta)`` is the distance of the nearest echo blocking ``theta`` (free directions
have none). Directions not sensed in the memory window count as free: the planner sees
less than TangentBug assumes, which is the point of comparing it on this robot.

* **Motion to goal**: if the goal direction is free, drive to the goal. Otherwise the
  obstacle that blocks it spans an interval of directions with two edges: the blocked
  directions round the goal direction whose ``rho`` does not jump by more than the grown
  radius (``radius + clearance``) from one direction to the next (a jump is a discontinuity
  of the range function: another obstacle, nearer or farther, with a gap between).
  The endpoint ``O`` of each edge is the first direction past it (free, or another
  obstacle's), at the distance of the boundary at the edge. (An interval of every blocked
  direction, whatever its ``rho``, took a box 0.6 m beside the robot and a wall 1 m beyond
  it for one obstacle, so the robot followed the box instead of the wall that blocked the
  way, lapped it and concluded ``unreachable``: issue 12, very_complex.)
  The robot heads for the endpoint minimising the heuristic distance
  ``h = |x - O| + |O - goal|``. When ``h`` has not improved on its minimum by ``h_epsilon``
  for ``stall_cycles`` cycles in which the robot moved (it *stops decreasing*), boundary following starts in the
  direction of that endpoint. (Also, as a safety reflex, when an echo lies in the corridor
  ahead closer than ``front_distance``: the sparse sonars can miss an obstacle between cones.)
* **Boundary following**: approach the boundary that blocks the way (head for the nearer of
  its points in the goal direction and at the chosen endpoint's edge, or for the nearest
  echo when following began for an echo ahead, until the follower's nearest point on the chosen side
  is within ``wall_distance + 0.15`` m or something is closer ahead than ``front_distance``),
  then keep it at ``wall_distance`` on that side with the sonar wall follower (one per side,
  both remembering echoes every cycle). ``d_followed`` is the
  smallest goal distance of the near echoes (within ``wall_distance + 0.6`` m) seen ahead
  and on the followed side since following began;
  ``d_reach`` is the goal distance of the farthest free point toward the goal
  (``d_goal - min(free length, d_goal)`` from the range function, evaluated only when the
  goal direction lies within the sonars' field of view). Leave when ``d_reach < d_followed - leave_margin``.
* **Unreachable**: back where following began (``loop_radius``) after a lap round the
  followed boundary (net turn toward the followed side) -> one more, *strict* lap (a
  ``replan`` event with ``reason="strict_lap"``): ``d_followed`` becomes the least goal
  distance of the follower's nearest side echo since following began, and takes only that
  echo from then on. The rule above also counts echoes of another obstacle across a passage
  (very_complex: a wall 1 m beyond the box being lapped), which can make leaving never pay
  (issue 12's false ``unreachable``); it stays in force until a lap closes because mazes are
  solved by it. A second lap -> stop and emit ``unreachable``.

Each switch to boundary following emits a ``replan`` event.

Cost per cycle (issue 16): the remembered echoes within ``R`` are turned into distances,
bearings and half angles once a cycle (:func:`polar_echoes`) and shared; the full circle of
``directions`` is evaluated only in motion-to-goal cycles whose goal direction is blocked, by
:func:`binned_range_function` (only the bins each echo can block, not every bin against every
echo); boundary following works out the free length toward the goal only when it can make the
robot leave. Each gives the plain computation's result bit for bit: recorded episodes replay
to the same commands (``tests/planners/test_tangent_bug.py``, ``benchmarks/bench_tangent_bug.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from nav_bench.interface import Command, Observation, wrap_angle
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
    echo_mask,
    obstacle_ahead,
    steer,
)


@dataclass(frozen=True)
class PolarEchoes:
    """Remembered echoes seen from one position, for the local range function (computed once
    a cycle and shared by its uses).

    Attributes:
        points: (M, 2) the echoes, world m.
        raw: (M,) their distance from the position, m.
        dist: (M,) ``raw`` but at least 1e-6 m.
        bearing: (M,) their world direction, rad in [-pi, pi].
        half: (M,) half angle each grown disc subtends, rad in [0, pi/2].
    """

    points: np.ndarray
    raw: np.ndarray
    dist: np.ndarray
    bearing: np.ndarray
    half: np.ndarray


def polar_echoes(points: np.ndarray, xy: np.ndarray, grow: float) -> PolarEchoes:
    """``points`` (M, 2) seen from ``xy`` (2,), each grown by ``grow`` m."""
    d = points - xy
    raw = np.hypot(d[:, 0], d[:, 1])
    dist = np.maximum(raw, 1e-6)
    bearing = np.arctan2(d[:, 1], d[:, 0])
    return PolarEchoes(points, raw, dist, bearing, np.arcsin(np.minimum(1.0, grow / dist)))


def range_function(points: np.ndarray | PolarEchoes, xy: np.ndarray, grow: float,
                   directions: np.ndarray) -> np.ndarray:
    """``rho`` (D,) of the local range function at ``xy``: for each direction (rad, world), the
    distance (m) of the nearest point of ``points`` (M, 2) whose grown disc (radius ``grow``)
    the ray passes; ``inf`` where none does. ``points`` may be given as :func:`polar_echoes`
    (then ``xy`` and ``grow`` are not used). Costs D x M: for a few directions; the full circle
    of bins is :func:`binned_range_function`."""
    e = points if isinstance(points, PolarEchoes) else polar_echoes(points, xy, grow)
    if len(e.dist) == 0:
        return np.full(len(directions), np.inf)
    diff = np.abs(np.remainder(directions[:, None] - e.bearing[None, :] + math.pi, 2 * math.pi) - math.pi)
    return np.where(diff <= e.half[None, :], e.dist[None, :], np.inf).min(axis=1)


def range_bins(n: int) -> np.ndarray:
    """(n,) directions of the binned range function, rad: ``-pi + 2 pi k / n``, CCW."""
    return np.linspace(-math.pi, math.pi, n, endpoint=False)


def binned_range_function(points: np.ndarray | PolarEchoes, xy: np.ndarray, grow: float,
                          bins: np.ndarray) -> np.ndarray:
    """:func:`range_function` over the directions ``bins`` = :func:`range_bins` ``(n)``, equal
    to it bit for bit, at a cost that grows with the bins the points block, not n x M.

    A point blocks the bins within its half angle of its bearing, a run of consecutive bins:
    only that run, widened by one bin on each side against rounding, is tested (a bin outside
    it is more than a whole bin, 0.05 rad at 120 bins, beyond the half angle: no rounding
    reaches that), with the expression of :func:`range_function`:
    ``|remainder(bin - bearing + pi, 2 pi) - pi| <= half``. The remainder is worked out only
    where its argument lies outside ``[0, 2 pi)`` (the run crosses the -pi/pi cut): inside, it is
    the argument itself, exactly. A bin's ``rho`` is the minimum distance of the points that
    block it, whatever their order. Bins are indexed ``k + n`` (in ``[0, 3n)``: a run reaches at
    most n/4 + 2 bins past either end of the circle) and folded back at the end."""
    n = len(bins)
    e = points if isinstance(points, PolarEchoes) else polar_echoes(points, xy, grow)
    if len(e.dist) == 0:
        return np.full(n, np.inf)
    step = 2 * math.pi / n
    lo_f = np.floor((e.bearing - e.half + math.pi) / step)
    hi_f = np.ceil((e.bearing + e.half + math.pi) / step)
    bearing, half, dist = e.bearing, e.half, e.dist
    finite = np.isfinite(lo_f) & np.isfinite(hi_f)
    if not finite.all():  # a NaN point blocks no direction (range_function: NaN <= x is False)
        lo_f, hi_f, bearing, half, dist = (a[finite] for a in (lo_f, hi_f, bearing, half, dist))
        if len(dist) == 0:
            return np.full(n, np.inf)
    lo = lo_f.astype(np.int64) - 1
    count = np.clip(hi_f.astype(np.int64) + 1 - lo + 1, 0, n)  # (M,) candidate bins; n covers the circle
    owner = np.repeat(np.arange(len(dist)), count)  # (C,) the point of each candidate
    k = np.repeat(lo + n - (np.cumsum(count) - count), count) + np.arange(len(owner))  # (C,) bin + n
    x = np.concatenate((bins, bins, bins))[k] - bearing[owner] + math.pi
    wrap = (x < 0.0) | (x >= 2 * math.pi)
    if wrap.any():
        x[wrap] = np.remainder(x[wrap], 2 * math.pi)
    hit = np.abs(x - math.pi) <= half[owner]
    rho = np.full(3 * n, np.inf)
    np.minimum.at(rho, k[hit], dist[owner[hit]])
    return np.minimum(np.minimum(rho[:n], rho[n:2 * n]), rho[2 * n:])


def obstacle_interval_edges(rho: np.ndarray, blocked: np.ndarray, k: int,
                            jump: float) -> tuple[int, int] | None:
    """The first bin clockwise and counter-clockwise past the *obstacle* that blocks bin ``k``
    (bins ordered CCW, circular): the run of blocked bins round ``k`` whose ``rho`` (m) does
    not jump by more than ``jump`` m from one bin to the next. A bin is past it when it is
    free or when its ``rho`` jumps: a discontinuity of the range function, where TangentBug
    puts an endpoint (Kamon et al. 1998). A bin whose ``rho`` is not finite (``k`` may be
    forced blocked) joins either neighbour. ``None`` if the run goes all round."""
    n = len(blocked)
    r, free = rho.tolist(), (~blocked).tolist()  # Python floats: a loop over them costs less

    def steps(direction: int) -> int | None:
        last = r[k]
        for i in range(1, n):
            b = (k + direction * i) % n
            if free[b] or (math.isfinite(last) and math.isfinite(r[b]) and abs(r[b] - last) > jump):
                return i
            last = r[b] if math.isfinite(r[b]) else last
        return None

    ccw, cw = steps(1), steps(-1)
    if ccw is None or cw is None:
        return None
    return (k - cw) % n, (k + ccw) % n


class OtherBoundaryLap:
    """Has the robot lapped a boundary other than the one it began following?

    The sonar wall follower keeps the nearest echo on its side, so where two obstacles stand
    closer than it keeps its distance it can pass from one boundary to the other and lap the
    second (congested, seed 0: it began on a long box, came down into the 0.6 m gap beside a
    smaller box and went round that one for 300 s). :class:`LoopDetector`, armed where following
    began, never fires there, and ``d_followed``, the least goal distance of the first boundary,
    is one the second never offers, so leaving never pays either. TangentBug's rules hold for
    the boundary being followed (Kamon et al. 1998), so this lap means: following of that
    boundary begins here.

    The run's positions are sampled every ``spacing`` m of travel with the travel and net turn
    (rad, CCW +) so far. It fires when the robot is back within ``radius`` of a sample that
    lies more than ``2 radius`` from where following began (there :class:`LoopDetector`
    decides), having been farther than ``2 radius`` from it since, travelled at least
    ``min_length`` and turned at least ``min_turn`` toward ``side`` since (the lap round an
    obstacle kept on that side: :class:`LoopDetector`'s rule).
    """

    def __init__(self, radius: float, min_length: float, min_turn: float = 1.5 * math.pi,
                 spacing: float = 0.05) -> None:
        self.radius, self.min_length, self.min_turn, self.spacing = radius, min_length, min_turn, spacing
        self.side = RIGHT
        self.origin = np.zeros(2)
        self._xy = np.zeros((0, 2))  # (N, 2) samples, m
        self._travel_at = np.zeros(0)  # (N,) travel when sampled, m
        self._turn_at = np.zeros(0)  # (N,) net turn when sampled, rad
        self._left = np.zeros(0, dtype=bool)  # (N,) been farther than 2 radius from it since?
        self._travel = self._turn = 0.0
        self._last_xy = np.zeros(2)
        self._last_yaw = 0.0

    def arm(self, xy: np.ndarray, yaw: float, side: int) -> None:
        """Start a run at ``xy`` (m), heading ``yaw`` (rad), boundary kept on ``side``."""
        self.side = side
        self.origin = np.asarray(xy, dtype=float).copy()
        self._xy, self._travel_at, self._turn_at = np.zeros((0, 2)), np.zeros(0), np.zeros(0)
        self._left = np.zeros(0, dtype=bool)
        self._travel = self._turn = 0.0
        self._last_xy, self._last_yaw = self.origin.copy(), float(yaw)

    def update(self, xy: np.ndarray, yaw: float) -> bool:
        """Feed the current position (m) and heading (rad); True on a lap of another boundary."""
        xy = np.asarray(xy, dtype=float)
        self._travel += math.hypot(xy[0] - self._last_xy[0], xy[1] - self._last_xy[1])
        self._turn += wrap_angle(float(yaw) - self._last_yaw)
        self._last_xy, self._last_yaw = xy.copy(), float(yaw)
        fired = False
        if len(self._xy):
            d = np.hypot(self._xy[:, 0] - xy[0], self._xy[:, 1] - xy[1])
            self._left |= d > 2 * self.radius
            fired = bool(np.any(self._left & (d < self.radius)
                                & (self._travel - self._travel_at >= self.min_length)
                                & (self.side * (self._turn - self._turn_at) >= self.min_turn)))
        last_travel = self._travel_at[-1] if len(self._travel_at) else -math.inf
        if (self._travel - last_travel >= self.spacing
                and math.hypot(xy[0] - self.origin[0], xy[1] - self.origin[1]) > 2 * self.radius):
            self._xy = np.vstack([self._xy, xy])
            self._travel_at = np.append(self._travel_at, self._travel)
            self._turn_at = np.append(self._turn_at, self._turn)
            self._left = np.append(self._left, False)
        return fired


class TangentBug(Planner):
    """TangentBug (Kamon, Rivlin & Rimon 1998) on a sonar ring with a short echo memory."""

    name: ClassVar[str] = "tangent_bug"
    reference: ClassVar[str] = ("Kamon, Rivlin & Rimon, TangentBug: A range-sensor-based navigation "
                                "algorithm, IJRR 17(9), 1998")
    params: ClassVar[tuple[Param, ...]] = (
        Param("v_max", 0.4, "m/s", "cruise speed (capped by the robot's limit)", minimum=0.0),
        Param("sensing_range", 0.0, "m", "range R of the local range function; 0 = the sonar max range",
              minimum=0.0),
        Param("memory_s", 8.0, "s", "how long sonar echoes are kept to build the range function",
              minimum=0.0),
        Param("clearance", 0.15, "m", "extra clearance added to the robot radius when growing echoes",
              minimum=0.0),
        Param("directions", 120, "-", "number of directions of the local range function", minimum=8),
        Param("h_epsilon", 0.05, "m", "the heuristic must beat its minimum by this to count as decreasing",
              minimum=0.0),
        Param("stall_cycles", 5, "cycles", "cycles without a decrease before boundary following", minimum=1),
        Param("front_distance", 0.45, "m", "echo this close ahead (from the centre) forces boundary following",
              minimum=0.0),
        Param("wall_distance", 0.4, "m", "distance kept from the followed boundary (robot centre)",
              minimum=0.0),
        Param("leave_margin", 0.1, "m", "leave when d_reach < d_followed - leave_margin", minimum=0.0),
        Param("loop_radius", 0.4, "m", "back within this of where following began after a lap = unreachable",
              minimum=0.0),
    )

    def reset(self, obs: Observation, rng: np.random.Generator) -> None:
        super().reset(obs, rng)
        p = self.settings
        self.memory = EchoMemory(p.memory_s)
        self.mode = GO
        self.h_min = math.inf
        self.stall = 0
        self.side = RIGHT
        self.follower: WallFollower | None = None
        # one follower per side, both watching every cycle: the one that takes over already
        # remembers the boundary it is to follow
        self.followers = {side: WallFollower(side, p.wall_distance, p.v_max, p.front_distance)
                          for side in (LEFT, RIGHT)}
        self.acquired = False
        self._blocking: np.ndarray | None = None  # where the approach to a boundary heads
        self.d_followed = math.inf
        self.d_followed_side = math.inf
        self.strict_lap = False
        self.loop = LoopDetector(p.loop_radius, min_length=4 * p.loop_radius)
        self.other_lap = OtherBoundaryLap(p.loop_radius, min_length=4 * p.loop_radius)
        self.bins = range_bins(p.directions)
        self._endpoint: list[float] | None = None
        self._prev_xy = np.asarray(obs.pose[:2], dtype=float).copy()
        self._follow_starts: list[list[float]] = []
        self._polar_echoes: PolarEchoes | None = None  # this cycle's; None: not computed yet
        sonar = obs.robot.sonar  # the sonars' field of view, half its width (rad)
        self._half_fov = float(np.max(np.abs(sonar.angles))) + sonar.cone / 2

    # -- the local range function ------------------------------------------------------------------
    def _sensing_range(self, obs: Observation) -> float:
        return self.settings.sensing_range or obs.robot.sonar.max_range

    def _polar(self, obs: Observation, xy: np.ndarray) -> PolarEchoes:
        """The remembered echoes within the sensing range seen from ``xy``: computed once a cycle
        (:meth:`act` drops them when it adds the cycle's echoes) and shared by the range
        functions and the approach to the boundary."""
        if self._polar_echoes is None:
            grow = obs.robot.radius + self.settings.clearance
            self._polar_echoes = polar_echoes(self.memory.points(xy, self._sensing_range(obs)), xy, grow)
        return self._polar_echoes

    def _free_length(self, obs: Observation, xy: np.ndarray, d_goal: float,
                     theta_g: float) -> tuple[float, float]:
        """(``rho`` toward the goal, free length toward the goal ``min(d_goal, R, rho)``), m."""
        rho_goal = float(range_function(self._polar(obs, xy), xy, 0.0, np.array([theta_g]))[0])
        return rho_goal, min(d_goal, self._sensing_range(obs), rho_goal)

    def _endpoints(self, obs: Observation, xy: np.ndarray, goal: np.ndarray, d_goal: float, theta_g: float
                   ) -> tuple[bool, list[tuple[float, float, int, np.ndarray]]]:
        """(goal direction free?, endpoints as (heading rad, h m, side to keep the obstacle on,
        (2,) the blocking obstacle's point at that edge, world m)).
        Motion to goal only: boundary following needs no endpoints, so never pays for the
        binned range function."""
        r_sense = self._sensing_range(obs)
        rho_goal, _ = self._free_length(obs, xy, d_goal, theta_g)
        if rho_goal >= d_goal:
            return True, []
        rho = binned_range_function(self._polar(obs, xy), xy, 0.0, self.bins)
        blocked = rho < d_goal
        n = len(self.bins)
        k_goal = int(np.argmin(np.abs(np.remainder(self.bins - theta_g + math.pi, 2 * math.pi) - math.pi)))
        blocked[k_goal] = True
        edges = obstacle_interval_edges(rho, blocked, k_goal, obs.robot.radius + self.settings.clearance)
        if edges is None:
            return False, []
        out = []
        for k_free, k_edge, side in ((edges[0], (edges[0] + 1) % n, LEFT),
                                     (edges[1], (edges[1] - 1) % n, RIGHT)):
            heading = float(self.bins[k_free])
            dist = min(float(rho[k_edge]), r_sense)
            o = xy + dist * np.array([math.cos(heading), math.sin(heading)])
            edge = float(self.bins[k_edge])
            blocking = xy + dist * np.array([math.cos(edge), math.sin(edge)])
            out.append((heading, dist + float(np.hypot(*(goal - o))), side, blocking))
        return False, out

    # -- control -----------------------------------------------------------------------------------
    def _start_following(self, obs: Observation, xy: np.ndarray, side: int,
                         blocking: np.ndarray | None = None) -> None:
        """Follow the boundary on ``side``; first approach ``blocking`` (world m), the obstacle
        that blocks the way to the goal (``None``: the nearest remembered echo)."""
        self.mode, self.side, self.acquired = FOLLOW, side, False
        self._blocking = blocking
        self.follower = self.followers[side]
        self.loop.side = side
        self._begin_boundary(obs, xy, "follow_boundary")

    def _begin_boundary(self, obs: Observation, xy: np.ndarray, reason: str) -> None:
        """Following of a boundary begins at ``xy`` (m) on ``self.side``: its own ``d_followed``
        (and ``d_followed_side``, from the follower's nearest side echo only) and laps, and a
        ``replan`` event with ``reason``."""
        self.d_followed = self.d_followed_side = math.inf
        self.strict_lap = False
        self._arm_laps(obs, xy)
        self._follow_starts.append([float(xy[0]), float(xy[1])])
        self._emit_replan(obs, reason)

    def _arm_laps(self, obs: Observation, xy: np.ndarray) -> None:
        """Count laps (round where following began, and round another boundary) from ``xy``."""
        self.loop.arm(xy, float(obs.pose[2]))
        self.other_lap.arm(xy, float(obs.pose[2]), self.side)

    def _emit_replan(self, obs: Observation, reason: str) -> None:
        self.emit("replan", obs.t, reason=reason, side="left" if self.side == LEFT else "right")

    def act(self, obs: Observation) -> Command:
        p = self.settings
        xy, goal = np.asarray(obs.pose[:2], dtype=float), np.asarray(obs.goal, dtype=float)
        self.memory.add(obs)
        for follower in self.followers.values():
            follower.observe(obs)
        self._polar_echoes = None  # the memory and the position changed
        v = min(p.v_max, obs.robot.v_max)
        d_goal = float(np.hypot(*(goal - xy)))
        theta_g = math.atan2(goal[1] - xy[1], goal[0] - xy[0])
        moved = float(np.hypot(*(xy - self._prev_xy)))
        self._prev_xy = xy.copy()
        if self.mode == FOLLOW:
            return self._follow(obs, xy, goal, d_goal, theta_g, v)
        if self.mode == UNREACHABLE:
            return STOP
        free, endpoints = self._endpoints(obs, xy, goal, d_goal, theta_g)
        ahead = obstacle_ahead(obs, p.front_distance, corridor_half_width(obs.robot))
        if free:
            self._endpoint = None
            self.h_min, self.stall = min(self.h_min, d_goal), 0
            if ahead < min(p.front_distance, d_goal):  # an obstacle the memory did not show
                side = RIGHT if wrap_angle(theta_g - float(obs.pose[2])) >= 0 else LEFT
                self._start_following(obs, xy, side)
                return self._follow(obs, xy, goal, d_goal, theta_g, v)
            return steer(obs, theta_g, arrival_speed(d_goal, v))
        if not endpoints:  # enclosed in every direction within range
            self._start_following(obs, xy, self.side)
            return self._follow(obs, xy, goal, d_goal, theta_g, v)
        heading, h, side, edge_point = min(endpoints, key=lambda e: e[1])
        if self._endpoint is None:  # the goal just got blocked: h starts afresh
            self.h_min, self.stall = math.inf, 0
        self._endpoint = [heading, h]
        if h < self.h_min - p.h_epsilon:
            self.h_min, self.stall = h, 0
        elif moved > 0.01:  # h_min is not lowered here, so a slow steady decrease still counts;
            self.stall += 1  # turning on the spot toward an endpoint is not a stall
        if self.stall >= p.stall_cycles or ahead < p.front_distance:
            # the obstacle to follow blocks the way to the goal: the nearer of its point in the
            # goal direction and its point at the chosen endpoint's edge
            rho_goal = self._free_length(obs, xy, d_goal, theta_g)[0]
            across = xy + rho_goal * np.array([math.cos(theta_g), math.sin(theta_g)])
            blocking = min((across, edge_point), key=lambda q: float(np.hypot(*(q - xy))))
            self._start_following(obs, xy, side, None if ahead < p.front_distance else blocking)
            return self._follow(obs, xy, goal, d_goal, theta_g, v)
        return steer(obs, heading, v)

    def _follow(self, obs: Observation, xy: np.ndarray, goal: np.ndarray, d_goal: float,
                theta_g: float, v: float) -> Command:
        p = self.settings
        assert self.follower is not None
        if self.other_lap.update(xy, float(obs.pose[2])):
            # the follower lapped a boundary other than the one following began on
            # (:class:`OtherBoundaryLap`): following of this one begins here, on the same side
            self._begin_boundary(obs, xy, "other_boundary")
        # near echoes ahead and on the followed side belong to the followed obstacle
        rel = self.side * obs.robot.sonar.angles
        near = np.asarray(obs.ranges) < p.wall_distance + 0.6
        side_echo = echo_mask(obs) & near & (rel > math.radians(-20))
        if side_echo.any() and not self.strict_lap:
            hits = obs.sonar_hits()[side_echo]
            self.d_followed = min(self.d_followed, float(np.hypot(*(hits - goal).T).min()))
        self.d_followed_side = min(self.d_followed_side, self._nearest_side_goal_distance(obs, xy, goal))
        if self.strict_lap:
            self.d_followed = self.d_followed_side
        if self.loop.update(xy, float(obs.pose[2])):
            if not self.strict_lap:
                self._start_strict_lap(obs, xy)
            else:
                self.mode = UNREACHABLE
                self.emit("unreachable", obs.t, x=float(xy[0]), y=float(xy[1]))
                return STOP
        # d_reach = d_goal - free length when the goal direction is in view, else inf (never
        # below d_followed): the free length is only worked out when it can make the robot leave
        if self.acquired and abs(wrap_angle(theta_g - float(obs.pose[2]))) <= self._half_fov:
            d_reach = d_goal - self._free_length(obs, xy, d_goal, theta_g)[1]
            if d_reach < self.d_followed - p.leave_margin:
                self.mode, self.h_min, self.stall, self._endpoint = GO, math.inf, 0, None
                self.loop.disarm()
                return steer(obs, theta_g, arrival_speed(d_goal, v))
        if not self.acquired:  # first approach the boundary that blocks the way
            return self._approach(obs, xy, v) or self.follower.act(obs)
        return self.follower.act(obs)

    def _nearest_side_goal_distance(self, obs: Observation, xy: np.ndarray, goal: np.ndarray) -> float:
        """Goal distance (m) of the follower's nearest echo on the followed side (the boundary
        it keeps), ``inf`` if there is none."""
        assert self.follower is not None
        boundary = self.follower.nearest(obs)
        if boundary is None:
            return math.inf
        dist, bearing = boundary
        point = xy + dist * np.array([math.cos(bearing), math.sin(bearing)])
        return float(np.hypot(*(point - goal)))

    def _start_strict_lap(self, obs: Observation, xy: np.ndarray) -> None:
        """A lap closed with ``d_followed`` from every near echo ahead and on the followed side:
        that rule also takes echoes of another obstacle across a passage (very_complex: a wall
        0.95-1.2 m beyond the box being lapped), so leaving may never have paid although the
        goal is reachable (issue 12). Lap once more with ``d_followed`` from the follower's
        nearest side echo only (the followed boundary); a second lap means unreachable. Until
        a first lap closes the rule is unchanged: mazes are solved by it."""
        self.strict_lap = True
        self.d_followed = self.d_followed_side
        self._arm_laps(obs, xy)  # the lap just closed went round this boundary
        self._emit_replan(obs, "strict_lap")

    def _approach(self, obs: Observation, xy: np.ndarray, v: float) -> Command | None:
        """Head for the blocking obstacle's point (or the nearest remembered echo) until the
        boundary is within ``wall_distance + 0.15`` m on the followed side or closer than
        ``front_distance`` ahead; then (or with nothing to head for) mark it acquired and
        return ``None``. Heading for the *nearest* echo made the robot follow whatever stood
        closest (a box beside it) instead of the wall across the way to the goal, and lap it."""
        p = self.settings
        assert self.follower is not None
        target = self._blocking
        if target is None:
            e = self._polar(obs, xy)
            target = e.points[int(np.argmin(e.raw))] if len(e.points) else None
        side_point = self.follower.nearest(obs)
        close = side_point is not None and side_point[0] <= p.wall_distance + 0.15
        near = obstacle_ahead(obs, p.front_distance, corridor_half_width(obs.robot)) < p.front_distance
        self.acquired = (target is None or close or near
                         or float(np.hypot(*(target - xy))) <= p.wall_distance + 0.1)
        if self.acquired:
            return None
        return steer(obs, math.atan2(target[1] - xy[1], target[0] - xy[0]), v)

    def debug_state(self) -> dict[str, Any]:
        """``mode``, ``memory`` (M, 2) remembered echoes, ``follow_starts`` [[x, y], ...] where
        boundary following began, ``endpoint`` [heading rad, h m] of the last chosen endpoint."""
        if not hasattr(self, "memory"):
            return {}
        return {"mode": self.mode, "memory": self.memory.points(),
                "follow_starts": [list(f) for f in self._follow_starts], "endpoint": self._endpoint}
