"""Pieces the baseline planners share: sonar geometry, command limits, heading and path
pursuit, a sonar wall follower and a short memory of sonar echoes.

Everything here reads only what an :class:`~nav_bench.planners.base.Observation` gives.
Frames: the robot frame has x forward and y to the left; the world frame is the episode's.
Units: metres, seconds, radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nav_bench.errors import InputError
from nav_bench.interface import Command, Observation, RobotInfo, wrap_angle

LEFT, RIGHT = 1, -1  # side signs: +1 = the robot's left (+y), -1 = its right
# modes of the bug family (Bug2, TangentBug): drive to the goal, follow a boundary, give up
GO, FOLLOW, UNREACHABLE = "motion_to_goal", "follow_boundary", "unreachable"


def corridor_half_width(robot: RobotInfo) -> float:
    """Half width (m) of the corridor ahead the robot sweeps, with 5 cm to spare on each side."""
    return robot.radius + 0.05


# ----------------------------------------------------------------------------- sonar geometry
def echo_mask(obs: Observation) -> np.ndarray:
    """(K,) bool: readings that are an echo (finite and below ``max_range``)."""
    r = np.asarray(obs.ranges, dtype=float)
    return np.isfinite(r) & (r < obs.robot.sonar.max_range)


def robot_frame_hits(obs: Observation) -> np.ndarray:
    """(K, 2) sonar return points in the robot frame (mount offset + range along the axis), m.

    Readings without an echo give the point at ``max_range``; combine with :func:`echo_mask`.
    """
    s = obs.robot.sonar
    r = np.where(np.isfinite(obs.ranges), obs.ranges, s.max_range)
    return s.offsets + r[:, None] * np.stack([np.cos(s.angles), np.sin(s.angles)], axis=1)


def world_echoes(obs: Observation) -> np.ndarray:
    """(M, 2) world-frame points of the readings that are echoes, m."""
    return obs.sonar_hits()[echo_mask(obs)]


def obstacle_ahead(obs: Observation, distance: float, half_width: float) -> float:
    """Distance (m, from the robot centre along its heading) to the nearest echo inside the
    corridor ``0 < x < distance``, ``|y| < half_width`` of the robot frame; ``inf`` if none.

    Uses the echo points on the sonar axes, so an obstacle between two sonar cones is missed:
    that is the sensing these planners have.
    """
    p = robot_frame_hits(obs)[echo_mask(obs)]
    inside = (p[:, 0] > 0.0) & (p[:, 0] < distance) & (np.abs(p[:, 1]) < half_width)
    return float(p[inside, 0].min()) if inside.any() else math.inf


def points_ahead(points: np.ndarray, obs: Observation, distance: float, half_width: float) -> float:
    """Like :func:`obstacle_ahead` for remembered world ``points`` (M, 2): distance (m, along
    the heading from the robot centre) to the nearest one in the corridor ``0 < x < distance``,
    ``|y| < half_width`` of the robot frame; ``inf`` if none. A post that is between the two
    front beams now was usually on one of them a second ago."""
    if len(points) == 0:
        return math.inf
    x, y, yaw = (float(v) for v in obs.pose[:3])
    d = points - np.array([x, y])
    c, s = math.cos(yaw), math.sin(yaw)
    fwd, lat = d[:, 0] * c + d[:, 1] * s, -d[:, 0] * s + d[:, 1] * c
    inside = (fwd > 0.0) & (fwd < distance) & (np.abs(lat) < half_width)
    return float(fwd[inside].min()) if inside.any() else math.inf


def free_along(points: np.ndarray, origin: np.ndarray, heading: float, length: float,
               half_width: float) -> bool:
    """True if none of the world ``points`` (M, 2) lies in the rectangle starting at ``origin``
    (2,) along ``heading`` (rad) for ``length`` m, ``half_width`` m to each side.

    Points behind ``origin`` are ignored: a cone sonar's echo placed on its axis can sit
    beside the robot although the surface it came from is farther away."""
    if len(points) == 0:
        return True
    d = points - origin
    c, s = math.cos(heading), math.sin(heading)
    along = d[:, 0] * c + d[:, 1] * s
    lateral = np.abs(-d[:, 0] * s + d[:, 1] * c)
    return not bool(np.any((along > 0.0) & (along < length) & (lateral < half_width)))


# ----------------------------------------------------------------------------- commands
def limit(v: float, omega: float, robot: RobotInfo) -> Command:
    """A finite command inside the robot's limits (NaN becomes 0)."""
    v = 0.0 if not math.isfinite(v) else max(-robot.v_max, min(robot.v_max, v))
    omega = 0.0 if not math.isfinite(omega) else max(-robot.omega_max, min(robot.omega_max, omega))
    return Command(float(v), float(omega))


STOP = Command(0.0, 0.0)


def steer(obs: Observation, heading: float, v_des: float, *, k_omega: float = 2.5,
          turn_in_place: float = math.radians(60.0)) -> Command:
    """Turn toward ``heading`` (rad, world) while driving at up to ``v_des`` m/s.

    The heading error sets ``omega = k_omega * error``; translation falls with ``cos(error)``
    and is zero when the error exceeds ``turn_in_place`` (a differential drive turns on the spot
    rather than driving a wide arc away from where it wants to go).
    """
    err = wrap_angle(heading - float(obs.pose[2]))
    omega = k_omega * err
    v = 0.0 if abs(err) > turn_in_place else v_des * max(0.0, math.cos(err))
    return limit(v, omega, obs.robot)


def arrival_speed(distance: float, v_des: float, slow_radius: float = 0.6) -> float:
    """Speed, m/s, easing in linearly over the last ``slow_radius`` m to a goal (never below 20 %)."""
    return v_des * min(1.0, max(0.2, distance / slow_radius))


def pure_pursuit(obs: Observation, path: np.ndarray, lookahead: float, v_des: float, *,
                 turn_in_place: float = math.radians(60.0)) -> Command:
    """Follow a polyline ``path`` (N, 2) (world, m; first point near the robot, last the goal).

    The lookahead point is the first path point at least ``lookahead`` m from the robot
    (the path's end if none). Curvature ``kappa = 2 sin(alpha) / L`` (Coulter 1992) with
    ``alpha`` the bearing of that point; the robot turns on the spot when ``|alpha|`` exceeds
    ``turn_in_place``, and slows so that ``|v * kappa| <= omega_max``.
    """
    xy = np.asarray(obs.pose[:2], dtype=float)
    if len(path) == 0:
        return STOP
    d = np.hypot(path[:, 0] - xy[0], path[:, 1] - xy[1])
    far = np.nonzero(d >= lookahead)[0]
    target = path[far[0]] if len(far) else path[-1]
    dist = float(np.hypot(*(target - xy)))
    if dist < 1e-9:
        return STOP
    alpha = wrap_angle(math.atan2(target[1] - xy[1], target[0] - xy[0]) - float(obs.pose[2]))
    if abs(alpha) > turn_in_place:
        return limit(0.0, 2.5 * alpha, obs.robot)
    v = arrival_speed(float(np.hypot(*(path[-1] - xy))), v_des)
    kappa = 2.0 * math.sin(alpha) / max(dist, 1e-6)
    if abs(v * kappa) > obs.robot.omega_max:
        v = obs.robot.omega_max / abs(kappa)
    return limit(v, v * kappa, obs.robot)


# ----------------------------------------------------------------------------- wall following
@dataclass(frozen=True)
class WallEstimate:
    """A wall seen by one side's sonars, in the robot frame.

    Attributes:
        distance: perpendicular distance from the robot centre to the wall line, m.
        angle: direction of the wall relative to the robot heading, rad; 0 = parallel,
            negative (wall on the left) / positive (wall on the right) = converging.
    """

    distance: float
    angle: float


def estimate_wall(obs: Observation, side: int, lost: float) -> WallEstimate | None:
    """Fit a straight wall to the readings of the sonars on ``side`` (LEFT/RIGHT) between 30
    and 120 deg from the heading (on the default ring: the 45 and 90 deg sonars).

    A cone sonar returns the *shortest* range within its cone, i.e. along the ray closest to
    the wall's normal, not along its axis. For a candidate normal direction ``a`` the ray is
    the axis clamped to the cone around ``a``; range ``r`` then means the wall lies at
    ``d = r cos(ray - a) + offset . n``. The normal direction whose distances agree best
    across the sonars is kept (1 deg grid search). With one sonar the wall is assumed
    parallel. Readings beyond ``lost`` m are ignored; ``None`` if none is left.
    """
    s = obs.robot.sonar
    rel = side * s.angles
    pick = (rel > math.radians(30)) & (rel < math.radians(120)) & echo_mask(obs)
    pick &= np.asarray(obs.ranges) < lost
    if not pick.any():
        return None
    ang, off, rng = s.angles[pick], s.offsets[pick], np.asarray(obs.ranges, dtype=float)[pick]
    half = s.cone / 2
    if len(rng) == 1:
        normals = np.array([side * math.pi / 2])
    else:
        normals = side * np.radians(np.arange(20.0, 161.0))  # wall normal candidates
    ray = np.clip(normals[:, None], ang[None, :] - half, ang[None, :] + half)  # (C, k)
    d = rng[None, :] * np.cos(ray - normals[:, None]) + (
        off[None, :, 0] * np.cos(normals[:, None]) + off[None, :, 1] * np.sin(normals[:, None]))
    best = int(np.argmin(d.max(axis=1) - d.min(axis=1)))
    normal = float(normals[best])
    return WallEstimate(distance=float(d[best].mean()), angle=wrap_angle(normal - side * math.pi / 2))


def diagonal_ranges(obs: Observation, side: int, angle: float) -> tuple[float, float]:
    """Readings (m, ``max_range`` if no echo) of the sonars nearest ``angle`` (rad) from the
    heading toward ``side`` and toward the other side."""
    s = obs.robot.sonar
    r = np.where(echo_mask(obs), np.asarray(obs.ranges, dtype=float), s.max_range)
    near = int(np.argmin(np.abs(s.angles - side * angle)))
    far = int(np.argmin(np.abs(s.angles + side * angle)))
    return float(r[near]), float(r[far])


class WallFollower:
    """Keep a wall on one side at a set distance using only the sonars (a reactive follower).

    Rules, in order: (1) something close ahead (front corridor) -> turn on the spot away
    from the wall side, or toward it while rounding a corner (the wall was fitted within the
    last ``corner_cycles`` cycles and is gone: the opening is on that side) or when the
    wall side's diagonal sonar sees open space the other does not (:func:`diagonal_ranges`);
    (2) a wall fitted on the followed side (:func:`estimate_wall`) -> steer to make it
    parallel at ``distance`` (or in the middle of a corridor narrower than twice that, so the
    far wall does not push the robot into the near one); (3) no wall in that side's beams ->
    circle the nearest echo of the last ``memory_s`` s on that side (within ``distance + 0.6``
    m) at ``distance``: a corner or post that has fallen between the beams or behind the
    last one is still followed; with no such echo, arc toward that side with radius
    ``distance``. "Ahead" in rule (1) also counts remembered echoes in the robot-wide
    corridor (:func:`points_ahead`), so a post between the two front beams is not driven into.

    Args:
        side: LEFT (+1) or RIGHT (-1), the side the wall is kept on.
        distance: wall distance to hold, m from the robot centre.
        speed: forward speed, m/s.
        front: clearance ahead (m from the centre) below which the robot turns on the spot.
        k_dist: turn rate per metre of distance error, rad/s/m. k_angle: per rad of wall angle, 1/s.
        corner_cycles: how long (control cycles) after losing the wall rule (1) turns toward it.
        memory_s: how long the follower remembers echoes (world frame from odometry, carved), s.
    """

    def __init__(self, side: int, distance: float, speed: float, front: float,
                 k_dist: float = 2.0, k_angle: float = 2.0, corner_cycles: int = 30,
                 memory_s: float = 6.0) -> None:
        if side not in (LEFT, RIGHT):
            raise InputError(f"wall follower side must be LEFT (+1) or RIGHT (-1), got {side!r}")
        self.side, self.distance, self.speed, self.front = side, distance, speed, front
        self.k_dist, self.k_angle = k_dist, k_angle
        self.corner_cycles = corner_cycles
        self._since_wall = corner_cycles + 1  # control cycles since a wall was last fitted
        self._acquired = False  # a wall has been fitted on the followed side since start()
        # the echoes of the last seconds: a wall or post that falls between the six beams
        # (beside and behind the robot while it rounds it) is still known
        self.memory = EchoMemory(memory_s, carve=True, spacing=0.03)

    def start(self) -> None:
        """Begin following a new boundary (forget the last wall seen)."""
        self._since_wall = self.corner_cycles + 1
        self._acquired = False  # a wall has been fitted on the followed side since start()
        self.memory.clear()

    def remembered(self, obs: Observation) -> np.ndarray:
        """(M, 2) remembered echoes (this cycle's included) in the robot frame, m."""
        x, y, yaw = (float(v) for v in obs.pose[:3])
        d = self.memory.points(np.array([x, y]), self.distance + 0.6) - np.array([x, y])
        c, s = math.cos(yaw), math.sin(yaw)
        return np.stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]], axis=1)

    def _orbit(self, obs: Observation, near: np.ndarray, v: float) -> Command:
        """Keep the nearest remembered echo ``near`` (robot frame, m) on the wall side at
        ``distance``: head along the tangent of the circle round it, corrected toward or away
        from it by the distance error. Rounding a corner this way circles the corner itself
        instead of an open-loop arc that loses a thin wall's end or a post."""
        s = self.side
        dist = float(np.hypot(*near))
        bearing = math.atan2(near[1], near[0])
        err = max(-0.8, min(0.8, 2.0 * (dist - self.distance)))
        heading = wrap_angle(bearing - s * math.pi / 2 + s * err)
        omega = 2.5 * heading
        v = 0.6 * v * max(0.0, math.cos(heading))
        return limit(v, omega, obs.robot)

    def act(self, obs: Observation) -> Command:
        robot = obs.robot
        s = self.side
        half_width = corridor_half_width(robot)
        self.memory.add(obs)
        pts = self.remembered(obs)
        wall = estimate_wall(obs, s, lost=self.distance + 0.6)
        self._since_wall = 0 if wall is not None else self._since_wall + 1
        self._acquired |= wall is not None
        ahead = min(obstacle_ahead(obs, self.front, half_width),
                    points_ahead(self.memory.points(), obs, self.front, robot.radius))
        if ahead < self.front:
            # Turn away from the wall (a concave corner) unless the way on is on the wall side:
            # rounding a corner that just ended there, or its diagonal sonar sees open space
            # the other diagonal does not (the robot came round a convex corner too wide and
            # now faces the far wall of the corridor it is turning into).
            toward, away = diagonal_ranges(obs, s, math.pi / 4)
            front_toward, front_away = diagonal_ranges(obs, s, math.radians(15))
            rounding = 0 < self._since_wall <= self.corner_cycles
            # open on the wall side at both the diagonal and the front sonar: the obstacle
            # ahead leans to the far side (in clutter a lone diagonal gap is too narrow)
            open_side = (toward > self.front + 0.3 and toward > away + 0.2
                         and front_toward > front_away + 0.05)
            # before any wall was on the followed side the obstacle ahead is the one just hit:
            # turn away to put it on that side (turning toward the open side there left the
            # wall on the other side and the robot arced round in open space)
            toward_ok = self._acquired and (rounding or open_side) and toward >= away
            turn = s if toward_ok else -s
            return limit(0.0, turn * 0.6 * robot.omega_max, robot)
        v = min(self.speed, robot.v_max)
        if wall is None:  # no wall in the side beams: round the remembered end, if any
            side_pts = pts[s * pts[:, 1] > 0.0]
            if len(side_pts):
                near = side_pts[int(np.argmin(np.hypot(side_pts[:, 0], side_pts[:, 1])))]
                return self._orbit(obs, near, v)
            radius = max(self.distance, 1e-3)
            return limit(0.6 * v, s * 0.6 * v / radius, robot)
        target = self.distance
        other = estimate_wall(obs, -s, lost=self.distance + 0.6)
        if other is not None:  # a corridor narrower than twice the distance: keep to its middle
            target = min(target, 0.5 * (wall.distance + other.distance))
        err = max(-0.5, min(0.5, wall.distance - target))
        omega = s * self.k_dist * err + self.k_angle * wall.angle
        v *= max(0.25, 1.0 - abs(omega) / robot.omega_max)
        return limit(v, omega, robot)


# ----------------------------------------------------------------------------- echo memory
class EchoMemory:
    """The sonar echoes of the last ``horizon`` seconds as world points (from the odometry pose).

    Six sonars sample the surroundings too sparsely to see an obstacle's outline in one
    cycle; remembering recent echoes lets a planner reason about what it just drove past.
    Odometry drift over a few seconds is small, so the points stay consistent.

    With ``carve`` a point is also forgotten when a later reading sees through it: a cone
    sonar returns the *nearest* surface in its cone, so a remembered point inside the inner
    part of a cone (``carve_cone`` of its half angle) and nearer than the reading by more than
    ``carve_margin`` is not there (it was a misplaced cone echo, or the robot's odometry moved
    it). That keeps a long memory (``horizon = inf``) truthful. ``spacing`` > 0 keeps one point
    per ``spacing`` m square (the newest), so a long memory stays small.

    Args:
        horizon: how long an echo is kept, s (``inf``: until carved or dropped by capacity).
        capacity: at most this many points are kept (oldest dropped first).
        carve: forget points later readings see through.
        spacing: side of the de-duplication squares, m (0: keep every echo).
    """

    def __init__(self, horizon: float, capacity: int = 4000, *, carve: bool = False,
                 spacing: float = 0.0, carve_margin: float = 0.15, carve_cone: float = 0.8) -> None:
        self.horizon, self.capacity = horizon, capacity
        self.carve, self.spacing = carve, spacing
        self.carve_margin, self.carve_cone = carve_margin, carve_cone
        self.clear()

    def clear(self) -> None:
        self._xy, self._t = np.zeros((0, 2)), np.zeros(0)
        # (M,) int64 code of each point's de-duplication square (with spacing > 0); the stored
        # points have distinct codes, so an add only compares its few new points against them
        self._square = np.zeros(0, dtype=np.int64)
        self._distances: tuple[tuple[float, float], np.ndarray] | None = None  # see points()

    def _square_codes(self, xy: np.ndarray) -> np.ndarray:
        """(M,) int64 code of the ``spacing`` m square of each point of ``xy`` (M, 2): the
        square's column in the high 32 bits, its row in the low 32 (distinct for |index| < 2**31,
        i.e. within 10**7 m of the origin at 5 cm)."""
        key = np.floor(xy / self.spacing).astype(np.int64)
        return key[:, 0] * (1 << 32) + key[:, 1]

    def _carve(self, obs: Observation) -> None:
        """Drop remembered points that this cycle's readings see through (vectorised over
        points x sonars). Only points that some reading could see through are examined: those
        within the longest reading less the margin of a sonar's origin (a box round the robot
        that contains them), so the cost does not grow with the whole memory."""
        if len(self._xy) == 0:
            return
        s = obs.robot.sonar
        x, y, yaw = (float(v) for v in obs.pose[:3])
        r = np.where(np.isfinite(obs.ranges), np.asarray(obs.ranges, dtype=float), s.max_range)
        reach = float(r.max()) - self.carve_margin
        if not reach > 0.0:
            return
        reach += float(np.hypot(s.offsets[:, 0], s.offsets[:, 1]).max()) + 1e-6  # from the centre
        near = np.flatnonzero((np.abs(self._xy[:, 0] - x) < reach) & (np.abs(self._xy[:, 1] - y) < reach))
        if len(near) == 0:
            return
        c, si = math.cos(yaw), math.sin(yaw)
        ox = x + c * s.offsets[:, 0] - si * s.offsets[:, 1]  # (K,) sonar origins
        oy = y + si * s.offsets[:, 0] + c * s.offsets[:, 1]
        dx = self._xy[near, 0][:, None] - ox[None, :]  # (N, K)
        dy = self._xy[near, 1][:, None] - oy[None, :]
        dist = np.hypot(dx, dy)
        # the bearing test only for the (point, sonar) pairs nearer than that reading
        i, k = np.nonzero(dist < r[None, :] - self.carve_margin)
        if len(i) == 0:
            return
        off = np.abs(np.remainder(np.arctan2(dy[i, k], dx[i, k]) - (yaw + s.angles)[k] + math.pi,
                                  2 * math.pi) - math.pi)
        seen = i[off <= self.carve_cone * s.cone / 2]
        if len(seen):
            keep = np.ones(len(self._xy), dtype=bool)
            keep[near[seen]] = False
            self._drop(keep)

    def _drop(self, keep: np.ndarray) -> None:
        """Keep only the points where ``keep`` (M,) bool is True."""
        self._xy, self._t = self._xy[keep], self._t[keep]
        self._distances = None
        if self.spacing > 0:
            self._square = self._square[keep]

    def add(self, obs: Observation) -> None:
        """Store this cycle's echoes and forget those older than the horizon (or seen through).

        With ``spacing`` the newest point of each square is kept, in the order the kept points
        were added (the de-duplication compares only this cycle's echoes with the memory)."""
        if self.carve:
            self._carve(obs)
        pts = world_echoes(obs)
        if len(self._t) and not self._t[0] >= obs.t - self.horizon:  # the oldest is first
            self._drop(self._t >= obs.t - self.horizon)
        t_new = np.full(len(pts), obs.t)
        if not obs.t >= obs.t - self.horizon:  # only a NaN time or a negative horizon drops new echoes
            pts, t_new = pts[:0], t_new[:0]
        if self.spacing > 0 and len(pts):
            codes = self._square_codes(pts)
            # the last echo of each square among this cycle's (at most one per sonar: a loop
            # over the readings, not over the memory)
            seen: set[int] = set()
            last = [i for i in range(len(codes) - 1, -1, -1)
                    if not (int(codes[i]) in seen or seen.add(int(codes[i])))][::-1]
            pts, t_new, codes = pts[last], t_new[last], codes[last]
            replaced = (self._square[:, None] == codes[None, :]).any(axis=1)
            if replaced.any():  # the newer echo of a square replaces the remembered one
                self._drop(~replaced)
            self._square = np.concatenate([self._square, codes])[-self.capacity:]
        self._xy = np.concatenate([self._xy, pts])[-self.capacity:]
        self._t = np.concatenate([self._t, t_new])[-self.capacity:]
        self._distances = None

    def points(self, center: np.ndarray | None = None, radius: float = math.inf) -> np.ndarray:
        """(M, 2) remembered points, optionally only those within ``radius`` m of ``center``.

        The points' distances from the last ``center`` are kept until the memory changes: a
        planner asks several times a cycle from where the robot is."""
        if center is None or not math.isfinite(radius):
            return self._xy.copy()
        at = (float(center[0]), float(center[1]))
        if self._distances is None or self._distances[0] != at:
            self._distances = (at, np.hypot(self._xy[:, 0] - at[0], self._xy[:, 1] - at[1]))
        return self._xy[self._distances[1] <= radius]

    def __len__(self) -> int:
        return len(self._xy)


# ----------------------------------------------------------------------------- loops
class LoopDetector:
    """Has the robot come back to where it started following a boundary, going the same way?

    Armed at a point; fires when the robot returns within ``radius`` m of it after having
    been farther than ``2 * radius``, having travelled at least ``min_length`` m, and moving
    (direction of its last 5 cm of displacement, not its yaw: turning on the spot sweeps the
    yaw) within 60 deg of the direction in which it first left the ``radius`` circle, and
    having turned by more than 1.5 pi in all (a lap round a boundary turns by 2 pi). The
    direction tests tell a lap from a U-turn: following a wall into a dead-end pocket brings
    the robot back past the arming point on the pocket's other wall, in a 1 m corridor within
    0.2 m of it, but going the opposite way, having turned by pi.
    """

    def __init__(self, radius: float, min_length: float) -> None:
        self.radius, self.min_length = radius, min_length
        self.origin: np.ndarray | None = None
        self._left = False
        self._travel = 0.0
        self._last: np.ndarray | None = None
        self._direction: float | None = None  # direction of the last displacement, rad
        self._exit_direction: float | None = None
        self._anchor = np.zeros(2)
        self._winding = 0.0  # total turn of the direction of motion since arming, rad

    def arm(self, xy: np.ndarray) -> None:
        self.origin = np.asarray(xy, dtype=float).copy()
        self._left, self._travel, self._last = False, 0.0, self.origin.copy()
        self._direction = self._exit_direction = None
        self._anchor = self.origin.copy()
        self._winding = 0.0

    def disarm(self) -> None:
        self.origin = None

    def update(self, xy: np.ndarray) -> bool:
        """Feed the current position; True when a full lap is detected."""
        if self.origin is None:
            return False
        xy = np.asarray(xy, dtype=float)
        if self._last is not None:
            self._travel += float(np.hypot(*(xy - self._last)))
        self._last = xy.copy()
        step = xy - self._anchor
        if float(np.hypot(*step)) >= 0.05:  # a direction from 5 cm of motion, not odometry jitter
            direction = math.atan2(step[1], step[0])
            if self._direction is not None:
                self._winding += wrap_angle(direction - self._direction)
            self._direction, self._anchor = direction, xy.copy()
        d = float(np.hypot(*(xy - self.origin)))
        if self._exit_direction is None and d > self.radius:
            self._exit_direction = self._direction
        if d > 2 * self.radius:
            self._left = True
        if not (self._left and d < self.radius and self._travel >= self.min_length):
            return False
        if self._direction is None or self._exit_direction is None:
            return True
        return (abs(wrap_angle(self._direction - self._exit_direction)) < math.radians(60)
                and abs(self._winding) > 1.5 * math.pi)
