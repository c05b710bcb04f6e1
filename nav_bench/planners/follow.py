"""Pieces the baseline planners share: sonar geometry, command limits, heading and path
pursuit, a sonar wall follower and a short memory of sonar echoes.

Everything here reads only what an :class:`~nav_bench.planners.base.Observation` gives.
Frames: the robot frame has x forward and y to the left; the world frame is the episode's.
Units: metres, seconds, radians.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from nav_bench.errors import InputError
from nav_bench.interface import (
    Command,
    Observation,
    RobotInfo,
    SonarInfo,
    once_per_observation,
    wrap_angle,
)

LEFT, RIGHT = 1, -1  # side signs: +1 = the robot's left (+y), -1 = its right
# modes of the bug family (Bug2, TangentBug): drive to the goal, follow a boundary, give up
GO, FOLLOW, UNREACHABLE = "motion_to_goal", "follow_boundary", "unreachable"


def corridor_half_width(robot: RobotInfo) -> float:
    """Half width (m) of the corridor ahead the robot sweeps, with 5 cm to spare on each side."""
    return robot.radius + 0.05


# ----------------------------------------------------------------------------- sonar geometry
def echo_mask(obs: Observation) -> np.ndarray:
    """(K,) bool: readings that are an echo (finite and below ``max_range``); read-only."""
    return once_per_observation(obs, "_echo_mask", _echo_mask)


def _echo_mask(obs: Observation) -> np.ndarray:
    r = np.asarray(obs.ranges, dtype=float)
    return np.isfinite(r) & (r < obs.robot.sonar.max_range)


def robot_frame_hits(obs: Observation) -> np.ndarray:
    """(K, 2) sonar return points in the robot frame (mount offset + range along the axis), m;
    read-only.

    Readings without an echo give the point at ``max_range``; combine with :func:`echo_mask`.
    """
    return once_per_observation(obs, "_robot_frame_hits", _robot_frame_hits)


def _robot_frame_hits(obs: Observation) -> np.ndarray:
    s = obs.robot.sonar
    r = np.where(np.isfinite(obs.ranges), obs.ranges, s.max_range)
    axes = np.empty((len(s.angles), 2))  # np.stack([cos, sin], axis=1) without its overhead
    axes[:, 0], axes[:, 1] = np.cos(s.angles), np.sin(s.angles)
    return s.offsets + r[:, None] * axes


def robot_frame_echoes(obs: Observation) -> tuple[tuple[float, float, float], ...]:
    """The echoes as Python floats, once per observation: ``(x, y, sonar angle)`` of each
    reading with an echo (:func:`robot_frame_hits`, :func:`echo_mask`), in sonar order. Six
    sonars: loops over these floats cost less than NumPy calls on (6,) arrays, and compare alike."""
    return once_per_observation(obs, "_robot_frame_echoes", _robot_frame_echoes)


def _robot_frame_echoes(obs: Observation) -> tuple[tuple[float, float, float], ...]:
    return tuple((x, y, angle) for (x, y), echo, angle in zip(
        robot_frame_hits(obs).tolist(), echo_mask(obs).tolist(), obs.robot.sonar.angles.tolist(),
        strict=True) if echo)


def world_echoes(obs: Observation) -> np.ndarray:
    """(M, 2) world-frame points of the readings that are echoes, m."""
    return obs.sonar_hits()[echo_mask(obs)]


def obstacle_ahead(obs: Observation, distance: float, half_width: float,
                   within: float = math.inf) -> float:
    """Distance (m, from the robot centre along its heading) to the nearest echo inside the
    corridor ``0 < x < distance``, ``|y| < half_width`` of the robot frame; ``inf`` if none.

    Uses the echo points on the sonar axes, so an obstacle between two sonar cones is missed:
    that is the sensing these planners have. ``within`` (rad) keeps only the sonars whose axis
    lies that close to the heading: a diagonal sonar's echo a few cm off a wall beside the
    robot lands inside the corridor ahead, although the way ahead is open.
    """
    nearest = math.inf
    for x, y, angle in robot_frame_echoes(obs):
        if abs(angle) <= within and 0.0 < x < distance and abs(y) < half_width:
            nearest = min(nearest, x)
    return nearest


def in_corridor(points: np.ndarray, distance: float, half_width: float) -> np.ndarray:
    """(M,) bool: robot-frame ``points`` (M, 2) inside the corridor ahead, ``0 < x < distance``
    and ``|y| < half_width`` (m)."""
    return (points[:, 0] > 0.0) & (points[:, 0] < distance) & (np.abs(points[:, 1]) < half_width)


def free_along(points: np.ndarray, origin: np.ndarray, heading: float, length: float,
               half_width: float, body: float = 0.0) -> bool:
    """True if none of the world ``points`` (M, 2) lies in the rectangle starting at ``origin``
    (2,) along ``heading`` (rad) for ``length`` m, ``half_width`` m to each side.

    Points behind ``origin`` are ignored: a cone sonar's echo placed on its axis can sit
    beside the robot although the surface it came from is farther away. So are points closer
    than ``body`` m to ``origin`` (the robot's radius): the robot stands there, so nothing
    does; such a point is an echo heard through a cone's edge and placed on its axis."""
    if len(points) == 0:
        return True
    d = points - origin
    c, s = math.cos(heading), math.sin(heading)
    along = d[:, 0] * c + d[:, 1] * s
    lateral = np.abs(-d[:, 0] * s + d[:, 1] * c)
    outside = d[:, 0] ** 2 + d[:, 1] ** 2 >= body * body
    return not bool(np.any((along > 0.0) & (along < length) & (lateral < half_width) & outside))


# ----------------------------------------------------------------------------- commands
def limit(v: float, omega: float, robot: RobotInfo) -> Command:
    """A finite command inside the robot's limits (NaN becomes 0)."""
    v = 0.0 if not math.isfinite(v) else max(-robot.v_max, min(robot.v_max, v))
    omega = 0.0 if not math.isfinite(omega) else max(-robot.omega_max, min(robot.omega_max, omega))
    return Command(float(v), float(omega))


STOP = Command(0.0, 0.0)


K_OMEGA = 2.5  # 1/s: turn rate per radian of heading error, steer's and every turn toward a heading here


def steer(obs: Observation, heading: float, v_des: float, *, k_omega: float = K_OMEGA,
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


class OdometrySpeed:
    """The robot's forward speed, m/s, from two consecutive odometry poses: the displacement
    along the current heading over the time between them (0 at the first pose, or when no time
    passed). The drive's acceleration limits make it lag the commands, which is what a brake or
    a footprint check needs to know. Call once per control cycle."""

    def __init__(self) -> None:
        self._pose: np.ndarray | None = None
        self._t = 0.0

    def __call__(self, obs: Observation) -> float:
        pose = np.asarray(obs.pose, dtype=float)
        prev, t_prev = self._pose, self._t
        self._pose, self._t = pose.copy(), obs.t
        if prev is None or obs.t <= t_prev:
            return 0.0
        d = pose[:2] - prev[:2]
        return float(d[0] * math.cos(pose[2]) + d[1] * math.sin(pose[2])) / (obs.t - t_prev)


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
        return limit(0.0, K_OMEGA * alpha, obs.robot)
    v = arrival_speed(float(np.hypot(*(path[-1] - xy))), v_des)
    kappa = 2.0 * math.sin(alpha) / max(dist, 1e-6)
    if abs(v * kappa) > obs.robot.omega_max:
        v = obs.robot.omega_max / abs(kappa)
    return limit(v, v * kappa, obs.robot)


# ----------------------------------------------------------------------------- wall following
class WallFollower:
    """Keep an obstacle boundary on one side at a set distance (a reactive tangent follower on
    a short memory of sonar echoes).

    Six sonar cones see a wall only in patches, and a straight-wall fit to the side sonars
    breaks down at every corner, door and 1 m corridor (the opposite wall, the wall ahead and a
    wall's end all enter the fit). The follower instead keeps the echoes of the last
    ``memory_s`` seconds as world points (:class:`EchoMemory`) and steers along the tangent of
    the *nearest* remembered point on the followed side, the boundary-following law of the
    bug algorithms (Lumelsky & Stepanov 1987; Choset et al., Principles of Robot Motion,
    2005, sec. 2.3): with that point at bearing ``beta`` and distance ``d``, the heading is
    ``beta - side * pi/2`` (the point on ``side``), turned toward the point by
    ``k_dist * (d - distance)`` (at most ``max_correction``). A wall's end stays the nearest
    point while the robot passes it, so the robot rounds it at ``distance``; a wall ahead
    becomes the nearest point as the robot nears it, so the robot turns away from it.

    Only the side sonar (axis within 30 deg of 90 deg on ``side``) is remembered: its echo of a
    wall beside the robot comes along its axis, where it is placed; a diagonal or front sonar
    hears a wall at a slant through its cone's edge, up to half a cone off its axis, and such
    points, remembered, drift into the way ahead as the robot turns. This cycle's echoes of all
    the sonars on ``side`` count too. Points count when their bearing in the robot frame lies
    between ``-ahead_margin`` (slightly toward the other side) and ``behind_limit`` on ``side``:
    the opposite wall of a corridor is never followed, nor the wall just left behind at a
    concave corner. An echo of the front sonars closer than ``front`` and not farther than the
    nearest side point (by ``ahead_slack``) is a wall ahead: the robot turns on the spot away
    from ``side``. When no point lies within ``distance + reach`` m, the boundary has ended out
    of reach: the robot arcs toward ``side`` with radius ``distance`` to find it again.

    Narrow passages (issue 12): held ``distance`` off one side of a passage the robot fits but
    narrower than ``2 * distance`` (0.50-0.69 m in the generated offices and clutter), the front
    sonars heard the other side through their cones' edges as a wall ahead, and the robot rocked.
    When the followed boundary and the other side's beside echo (:meth:`other_side_clearance`)
    span such a passage, the robot holds its middle, and an other-side front echo that the
    cone's edge meeting that side explains is not a wall ahead unless the followed side's front
    sonar hears the way blocked too; it drives on until a wall ahead is as near as its side
    (plus ``ahead_slack``), then turns on the spot. Measured: results/baselines/bugs_s7n/summary.md.
    Between the two rules (an echo ahead nearer than ``front`` but farther than the side plus
    ``ahead_slack``) the robot turns on the spot toward the tangent, at least at
    ``band_turn_rate`` (:meth:`_band_turn`; it used to stand there: results/baselines/follow_s16).
    At a junction of 0.57-0.66 m gaps the turn away and the drive to the next gap's mouth, off
    its middle, made a limit cycle: full turns away from the side on the spot until the episode
    ended ``oscillating`` (results/baselines/follow_s17). While ``circling``
    (:class:`CirclingDetector`, updated by :meth:`act`) says so, and only then, the robot
    steers onto the middle line of the gap whose far corner blocks the corridor ahead
    (:meth:`_centring_heading`) instead of turning away: a recovery behaviour, like a
    navigation stack's when its progress checker fails (results/baselines/follow_s18).

    Args:
        side: LEFT (+1) or RIGHT (-1), the side the wall is kept on.
        distance: boundary distance to hold, m from the robot centre.
        speed: forward speed, m/s.
        front: clearance ahead (m from the centre) below which the robot turns on the spot.
        k_dist: heading correction per metre of distance error, rad/m.
        memory_s: how long echoes are remembered, s.
        reach: how far beyond ``distance`` (m) a remembered point still counts as the boundary.
    """

    ahead_margin = math.radians(10.0)
    max_correction = math.radians(60.0)
    behind_limit = math.radians(135.0)
    side_sonar_axis, side_sonar_window = math.pi / 2, math.radians(30.0)
    front_sonars = math.radians(30.0)  # sonars this close to the heading watch the way ahead
    ahead_slack = 0.1  # m: an echo ahead this much farther than the side's still counts as nearest
    beside_sonars = math.radians(40.0)  # other-side sonars this far off the heading measure a passage
    edge_slack = 0.08  # m: a front echo this close to the other side's edge range is that side
    max_turn_rate = 2.0  # rad/s: the turn on the spot's cap (11.5 deg a cycle at 10 Hz), see turn_rate
    corner_lead = math.radians(30.0)  # a followed point this far ahead of beside is a corner to round, see _passage_axis
    sweep_memory_s = 1.0  # s: readings whose cones the gap check (_axis_clear) takes into account
    sweep_radius = 1.0  # m: only echoes this close to the robot can meet its body swept through a gap
    sweep_margin = 0.02  # m: clearance beyond the radius the swept body must keep from every cone's arc
    arc_samples = 7  # bearings sampled across a cone's arc by _axis_clear
    free_slack = 0.05  # m: a cone is taken as free of surfaces up to its reading less this
    # rad/s: the least turn in the dead band, see _band_turn: the distance correction's own turn
    # at 6 cm of distance error (K_OMEGA k_dist 0.06), 1.7 deg a 10 Hz cycle, a quarter turn in 5 s
    band_turn_rate = 0.3

    def __init__(self, side: int, distance: float, speed: float, front: float,
                 k_dist: float = 2.0, memory_s: float = 3.0, reach: float = 0.6) -> None:
        if side not in (LEFT, RIGHT):
            raise InputError(f"wall follower side must be LEFT (+1) or RIGHT (-1), got {side!r}")
        self.side, self.distance, self.speed, self.front = side, distance, speed, front
        self.k_dist, self.reach = k_dist, reach
        self.memory = EchoMemory(memory_s)
        # the last sweep_memory_s of readings, (t, x, y, yaw, ranges) each, for _axis_clear
        self._readings: deque[tuple[float, float, float, float, np.ndarray]] = deque()
        self._seen_t = -math.inf  # time of the last cycle remembered
        # nearest()'s answer for the observation it was asked about (TangentBug asks, then its
        # follower's act() asks again in the same cycle); cleared when the memory changes
        self._nearest_of: tuple[Observation, tuple[float, float] | None] | None = None
        self._groups_of: SonarInfo | None = None  # the sonar ring of ``_groups``
        self.circling = CirclingDetector(side)  # updated by act(): turns on the recovery

    def _sonar_groups(self, sonar: SonarInfo) -> tuple[np.ndarray, np.ndarray]:
        """(K,) bool each: the side sonars whose echoes are remembered, and the sonars on the
        followed side. Worked out once per sonar ring (fixed for an episode), not every cycle."""
        if sonar is not self._groups_of:
            angles = self.side * sonar.angles
            self._groups = (np.abs(angles - self.side_sonar_axis) <= self.side_sonar_window, angles > 0.0)
            self._groups_of = sonar
        return self._groups

    def observe(self, obs: Observation) -> None:
        """Remember this cycle's echoes, once per cycle (:meth:`act` calls it; a planner calls it
        in the cycles it does not follow, so the memory has no gap when following starts)."""
        if obs.t > self._seen_t:
            self.memory.add(obs, self._sonar_groups(obs.robot.sonar)[0])
            self._remember_reading(obs)
            self._seen_t = obs.t
            self._nearest_of = None

    def _remember_reading(self, obs: Observation) -> None:
        """Keep this cycle's pose and ranges (the cones, not only their axis points) for
        :meth:`_axis_clear`, and forget those older than ``sweep_memory_s``."""
        x, y, yaw = (float(q) for q in obs.pose)
        self._readings.append((float(obs.t), x, y, yaw, np.asarray(obs.ranges, dtype=float)))
        while self._readings and self._readings[0][0] < obs.t - self.sweep_memory_s:
            self._readings.popleft()

    def _arc_points(self, obs: Observation) -> np.ndarray:
        """(M, 2) world points (m) where the remembered echoes' surfaces may be
        (:meth:`_remember_reading`). A sonar reports the nearest surface anywhere in its cone,
        so the surface may lie anywhere on the arc at that range about the mount, not only on
        the axis: ``arc_samples`` bearings across each cone. A sample that lies inside another
        remembered cone nearer than that reading's range less ``free_slack`` is dropped: that
        sonar heard nothing there (without this the arcs of a 0.55 m gap's corners fill it:
        the check never passed at Bug2 office_2). Only echoes whose axis point is within
        ``sweep_radius`` of the robot are sampled."""
        s = obs.robot.sonar
        rows = list(self._readings)
        poses = np.array([row[1:4] for row in rows])  # (N, 3)
        ranges = np.stack([row[4] for row in rows])  # (N, K)
        c, sn = np.cos(poses[:, 2:3]), np.sin(poses[:, 2:3])
        mount_x, mount_y = s.mounts(poses[:, 0:1], poses[:, 1:2], c, sn)  # (N, K)
        axis = poses[:, 2:3] + s.angles  # (N, K)
        r = np.where(np.isfinite(ranges), ranges, s.max_range)
        dx = mount_x + r * np.cos(axis) - float(obs.pose[0])
        dy = mount_y + r * np.sin(axis) - float(obs.pose[1])
        keep = (r < s.max_range) & (dx * dx + dy * dy <= self.sweep_radius ** 2)
        if not keep.any():
            return np.zeros((0, 2))
        spread = np.linspace(-s.cone / 2, s.cone / 2, self.arc_samples)
        bearing = axis[keep][:, None] + spread  # (M, S)
        px = (mount_x[keep][:, None] + r[keep][:, None] * np.cos(bearing)).ravel()
        py = (mount_y[keep][:, None] + r[keep][:, None] * np.sin(bearing)).ravel()
        # every remembered cone, echo or not, clears what lies nearer than its reading
        ex, ey = px[:, None] - mount_x.ravel(), py[:, None] - mount_y.ravel()  # (P, N K)
        off_axis = np.abs(np.remainder(np.arctan2(ey, ex) - axis.ravel() + math.pi, 2 * math.pi) - math.pi)
        seen_free = (off_axis < s.cone / 2) & (ex * ex + ey * ey < (r.ravel() - self.free_slack) ** 2)
        possible = ~seen_free.any(axis=1)
        return np.stack([px[possible], py[possible]], axis=1)

    def _axis_clear(self, obs: Observation, heading: float) -> bool:
        """True if the robot's body, swept from where it stands along ``heading`` (rad, world)
        for ``front`` m, keeps ``radius + sweep_margin`` m from every point of the remembered
        echoes' arcs (:meth:`_arc_points`, each echo taken anywhere on its cone's arc). Points
        behind the robot, or inside its body where it stands (free: the robot is there; the arc
        crosses it where the cone's nearest ray was not), are left out.

        The gap check of the passage axis: at a gap between two convex corners the axis leads
        into a 0.5-0.6 m gap that leaves 0.1 m a side, and the other side's point is a guess
        on one ray of its cone (results/baselines/follow_s13c)."""
        pts = self._arc_points(obs)
        if len(pts) == 0:
            return True
        d = pts - np.asarray(obs.pose[:2], dtype=float)
        c, s = math.cos(heading), math.sin(heading)
        along = d[:, 0] * c + d[:, 1] * s
        lateral = -d[:, 0] * s + d[:, 1] * c
        beyond = along - np.clip(along, 0.0, self.front)  # past the swept segment's end, m
        gap2 = beyond * beyond + lateral * lateral  # squared distance to the swept segment
        radius = obs.robot.radius
        inside = d[:, 0] ** 2 + d[:, 1] ** 2 < radius * radius
        clear = radius + self.sweep_margin
        return not bool(np.any((along > 0.0) & (gap2 < clear * clear) & ~inside))

    def nearest(self, obs: Observation) -> tuple[float, float] | None:
        """(distance m, world bearing rad) of the nearest echo on the followed side within
        ``distance + reach`` m, among the remembered side-sonar echoes and this cycle's echoes
        of every sonar on that side (a diagonal sonar sees a door jamb's end before the side
        sonar does; its axis placement is off by up to half a cone, too much to remember, but
        right enough now); ``None`` if there is none."""
        if self._nearest_of is not None and self._nearest_of[0] is obs:
            return self._nearest_of[1]
        found = self._nearest(obs)
        self._nearest_of = (obs, found)
        return found

    def _nearest(self, obs: Observation) -> tuple[float, float] | None:
        xy = np.asarray(obs.pose[:2], dtype=float)
        now = obs.sonar_hits()[echo_mask(obs) & self._sonar_groups(obs.robot.sonar)[1]]
        pts = np.concatenate([self.memory.points(xy, self.distance + self.reach), now])
        if len(pts) == 0:
            return None
        d = pts - xy
        bearing = np.arctan2(d[:, 1], d[:, 0])
        rel = self.side * np.remainder(bearing - float(obs.pose[2]) + math.pi, 2 * math.pi) - self.side * math.pi
        on_side = (rel >= -self.ahead_margin) & (rel <= self.behind_limit)
        if not on_side.any():
            return None
        dist = np.hypot(d[:, 0], d[:, 1])
        i = int(np.argmin(np.where(on_side, dist, np.inf)))
        return float(dist[i]), float(bearing[i])

    def other_side_clearance(self, obs: Observation) -> float:
        """Lateral distance (m, from the robot centre) of the nearest echo on the side *not*
        followed, from the sonars at least ``beside_sonars`` off the heading on that side, whose
        echo point lies beside the robot or a little ahead (``-radius < x < front`` in the robot
        frame); ``inf`` if none. With the followed boundary's distance it gives the
        width of the passage the robot is in."""
        echo = self._other_side_echo(obs)
        return math.inf if echo is None else -self.side * echo[1]

    def _far_corner_clearance(self, obs: Observation) -> float:
        """Lateral distance (m, from the robot centre) of the nearest echo of the other side's
        front sonars (less than ``beside_sonars`` off the heading) inside the corridor ahead
        (``0 < x < front``, ``|y| <`` :func:`corridor_half_width`), while the followed side's
        front sonars hear nothing there; ``inf`` if none: the far corner of a gap that the
        robot enters off its middle line."""
        half = corridor_half_width(obs.robot)
        nearest, followed_clear = math.inf, True
        for x, y, angle in robot_frame_echoes(obs):
            if not (abs(angle) <= self.front_sonars and 0.0 < x < self.front and abs(y) < half):
                continue
            if self.side * angle >= 0.0:
                followed_clear = False
            elif -self.side * angle < self.beside_sonars:
                nearest = min(nearest, max(-self.side * y, 0.0))
        return nearest if followed_clear else math.inf

    def _centring_heading(self, obs: Observation, near: tuple[float, float] | None) -> float | None:
        """World heading (rad) onto the middle line of a gap whose far corner
        (:meth:`_far_corner_clearance`) blocks the corridor ahead, when the gap between it and
        the followed point ``near`` (distance m, world bearing rad) fits the body with
        ``sweep_margin`` a side, the robot is nearer the corner than the followed side, and the
        body swept that way clears (:meth:`_axis_clear`); else ``None``. Issue 12: at office_2's
        junction the robot came into a 0.59 m channel 0.1 m off its middle, met the far corner,
        turned away on the spot and circled (results/baselines/follow_s17a). :meth:`act` asks
        only while the follower circles (results/baselines/follow_s18)."""
        if near is None:
            return None
        corner = self._far_corner_clearance(obs)
        dist, bearing = near
        width = dist + corner
        # the body and the swept check's margin, not the corridor's 5 cm a side: the corner's
        # echo, placed on the sonar's axis, reads 4-5 cm inside the gap (0.45 m for office_2's
        # 0.59 m one), and _axis_clear guards the body on its way in
        if not (2.0 * (obs.robot.radius + self.sweep_margin) <= width and corner < dist):
            return None
        correction = min(self.max_correction, self.k_dist * (dist - 0.5 * width))
        heading = bearing - self.side * math.pi / 2 + self.side * correction
        return heading if self._axis_clear(obs, heading) else None

    def _other_side_echo(self, obs: Observation) -> tuple[float, float, float] | None:
        """The echo :meth:`other_side_clearance` measures, as in :func:`robot_frame_echoes`."""
        nearest, found = math.inf, None
        for x, y, angle in robot_frame_echoes(obs):
            lateral = -self.side * y
            if -self.side * angle >= self.beside_sonars and -obs.robot.radius < x < self.front and 0.0 < lateral < nearest:
                nearest, found = lateral, (x, y, angle)
        return found

    def _other_side_point(self, obs: Observation) -> tuple[float, float]:
        """Robot-frame point (x, y) m of the other side's echo (:meth:`_other_side_echo`) placed
        on its cone's ray nearest to the perpendicular of the heading, not on its axis: a
        sonar's nearest return from a wall parallel to the heading comes along that ray, so
        beside such a wall the point is on the wall, where the axis point of a 45 deg sonar
        sits 0.2 m too far ahead."""
        x, y, angle = self._other_side_echo(obs)
        s = obs.robot.sonar
        k = int(np.argmin(np.abs(s.angles - angle)))
        mx, my = float(s.offsets[k, 0]), float(s.offsets[k, 1])
        r = math.hypot(x - mx, y - my)
        ray = angle + max(-s.cone / 2, min(s.cone / 2, -self.side * math.pi / 2 - angle))
        return mx + r * math.cos(ray), my + r * math.sin(ray)

    def _passage_axis(self, obs: Observation, near: tuple[float, float]) -> float:
        """World heading (rad) along a narrow passage between the followed boundary's nearest
        point and the other side's echo (:meth:`_other_side_point`): at right angles to the line
        joining them, the followed point on ``side``. Beside two parallel walls it is the
        followed wall's tangent. At a gap whose sides are two convex corners, the followed
        corner's tangent points across the gap, at the far corner, and the robot turned away
        from the gap (class A, results/baselines/follow_s13); the axis leads through it."""
        x, y, yaw = (float(q) for q in obs.pose)
        dist, bearing = near
        px, py = self._other_side_point(obs)
        c, s = math.cos(yaw), math.sin(yaw)
        other_x, other_y = x + c * px - s * py, y + s * px + c * py
        near_x, near_y = x + dist * math.cos(bearing), y + dist * math.sin(bearing)
        return math.atan2(near_y - other_y, near_x - other_x) - self.side * math.pi / 2

    def _edge_echo_explained(self, obs: Observation, other: float) -> np.ndarray:
        """(K,) bool: sonars on the other side whose reading is within ``edge_slack`` of the
        range at which their cone's outer edge meets a wall parallel to the heading at lateral
        distance ``other`` (m): that echo is the passage's other side, heard through the cone's
        edge and placed on the axis, not a wall ahead. (A reading much shorter or longer comes
        from something else: the cone reports its nearest ray.)"""
        s = obs.robot.sonar
        off = -self.side * s.offsets[:, 1]  # mount's lateral offset toward the other side, m
        edge = np.clip(-self.side * s.angles + s.cone / 2, 1e-3, math.pi / 2)
        reach = (other - off) / np.sin(edge)  # range to that wall along the cone's edge, m
        r = np.where(np.isfinite(obs.ranges), obs.ranges, s.max_range)
        return (-self.side * s.angles > 0.0) & (np.abs(r - reach) <= self.edge_slack)

    def _ahead(self, obs: Observation, other: float) -> float:
        """:func:`obstacle_ahead` within ``front``, leaving out in a narrow passage (``other``
        finite) the other side's front echoes that the passage's other side explains, as long
        as the followed side's front sonars hear nothing in the corridor straight ahead."""
        robot = obs.robot
        half = corridor_half_width(robot)
        ahead = obstacle_ahead(obs, self.front, half, within=self.front_sonars)
        if not (ahead < self.front and math.isfinite(other)):
            return ahead
        s = robot.sonar
        watching = np.abs(s.angles) <= self.front_sonars  # the sonars that watch the way ahead
        blocking = echo_mask(obs) & watching & in_corridor(robot_frame_hits(obs), self.front, half)
        if np.any(blocking & (self.side * s.angles >= 0.0)):
            return ahead  # the followed side's front sonar hears it too: a wall ahead
        if np.all(self._edge_echo_explained(obs, other)[blocking]):
            return math.inf
        return ahead

    def turn_rate(self, robot: RobotInfo) -> float:
        """Rate (rad/s) of the turn on the spot away from a wall ahead: ``0.6 omega_max``, at
        most ``max_turn_rate``. The simulated robot's 0.6 omega_max is 3.5 rad/s, 20 deg a
        10 Hz cycle: at the mouth of a 0.5-0.65 m gap between two convex obstacles the headings
        whose corridor ahead is clear span less than that, so the turn stepped over them, the
        robot turned full circles on the spot and the episode ended ``oscillating`` (issue 12:
        results/baselines/bugs_s8/classification.md)."""
        return min(0.6 * robot.omega_max, self.max_turn_rate)

    def act(self, obs: Observation) -> Command:
        self.circling.update(obs.t, *(float(q) for q in obs.pose))
        return self._act(obs)

    def _act(self, obs: Observation) -> Command:
        robot = obs.robot
        self.observe(obs)
        v = min(self.speed, robot.v_max)
        near = self.nearest(obs)
        target, other = self.distance, math.inf
        if near is not None:
            other = self.other_side_clearance(obs)
            width = near[0] + other
            if 2.0 * corridor_half_width(robot) <= width < 2.0 * self.distance:
                # a passage the robot fits through but narrower than the follower's distance
                # on both sides: hold its middle (narrower ones are part of the obstacle; slowing
                # down here lost time-limited episodes: results/baselines/bugs_s7n/summary.md)
                target = 0.5 * width
            else:
                other = math.inf
        ahead = self._ahead(obs, other)
        # in a narrow passage the followed side is nearer than ``distance``: the robot drives on
        # until a wall ahead is as near as that side (+ ahead_slack) and then turns, rather than
        # stop short of it, where neither rule below would move it again
        front = self.front if math.isinf(other) else min(self.front, target + self.ahead_slack)
        # the recovery from the junction's limit cycle, only while the follower circles (the
        # centring everywhere took the robot into gaps that the turn away kept it out of, and
        # those were grazed: results/baselines/follow_s17a, follow_s18)
        centring = self._centring_heading(obs, near) if self.circling.fired else None
        if centring is not None:
            return steer(obs, centring, 0.5 * v)
        if ahead < front and (near is None or ahead <= near[0] + self.ahead_slack):
            # the nearest boundary is straight ahead: its tangent is a right angle away from
            # the side; turn on the spot until the way ahead is clear
            return limit(0.0, -self.side * self.turn_rate(robot), robot)
        if near is None:  # the boundary ended out of reach: arc round toward it
            return limit(0.6 * v, self.side * 0.6 * v / max(self.distance, 1e-3), robot)
        dist, bearing = near
        correction = max(-self.max_correction, min(self.max_correction, self.k_dist * (dist - target)))
        corner_ahead = self.side * wrap_angle(bearing - float(obs.pose[2])) < math.pi / 2 - self.corner_lead
        tangent = bearing - self.side * math.pi / 2
        if corner_ahead and math.isfinite(other):
            # a gap between two corners: along its axis if the body swept that way clears
            # wherever the echoes may be, else round the followed corner as before
            axis = self._passage_axis(obs, near)
            if self._axis_clear(obs, axis):
                tangent = axis
        heading = tangent + self.side * correction
        if ahead < front:  # an echo ahead, but farther than the side: the band between the rules
            return self._band_turn(obs, heading, correction)
        return steer(obs, heading, v)

    def _band_turn(self, obs: Observation, heading: float, correction: float) -> Command:
        """The command when an echo ahead is nearer than ``front`` but farther than the followed
        side (+ ``ahead_slack``): turn on the spot toward ``heading`` (rad, world: the tangent
        with the distance correction ``correction``, rad), at least at ``band_turn_rate``.

        There the robot used to stand: v = 0, turning only by the distance correction, which is
        near zero when the side is near its distance (issue 12, the dead band:
        results/baselines/follow_s13). Turning *away* from the side at ``turn_rate`` instead made
        new pirouettes at junctions of narrow gaps (follow_s13, candidate A); the slow turn
        toward the tangent is what let the robot out of them, so it is kept and given a floor.
        With the robot on ``heading`` already, it turns the way of the correction (away from
        the side if the correction is zero)."""
        err = wrap_angle(heading - float(obs.pose[2]))
        way = math.copysign(1.0, err) if err != 0.0 else (
            math.copysign(1.0, self.side * correction) if correction != 0.0 else -self.side)
        return limit(0.0, way * max(K_OMEGA * abs(err), self.band_turn_rate), obs.robot)


# ----------------------------------------------------------------------------- echo memory
class EchoMemory:
    """The sonar echoes of the last ``horizon`` seconds as world points (from the odometry pose).

    Six sonars sample the surroundings too sparsely to see an obstacle's outline in one
    cycle; remembering recent echoes lets a planner reason about what it just drove past.
    Odometry drift over a few seconds is small, so the points stay consistent.

    The memory is, after each :meth:`add`, the earlier points and this cycle's echoes, oldest
    first, less those older than ``now - horizon``, then the last ``capacity`` of them. Kept in
    a buffer: while the echo times never decrease (a cycle's time only grows) the points the
    horizon drops are a prefix, found by bisection, and a cycle's echoes are appended in place
    (no copy of the whole memory per cycle); otherwise the memory is rebuilt by concatenating
    and masking. Both give the same points in the same order.

    Args:
        horizon: how long an echo is kept, s.
        capacity: at most this many points are kept (oldest dropped first).
    """

    def __init__(self, horizon: float, capacity: int = 4000) -> None:
        self.horizon, self.capacity = horizon, capacity
        self.clear()

    def clear(self) -> None:
        self._buf_xy, self._buf_t = np.zeros((0, 2)), np.zeros(0)
        self._lo = self._hi = 0  # the memory is _buf_xy[_lo:_hi] (times _buf_t[_lo:_hi])
        self._sorted = True  # its times never decrease

    @property
    def _xy(self) -> np.ndarray:
        return self._buf_xy[self._lo:self._hi]

    @property
    def _t(self) -> np.ndarray:
        return self._buf_t[self._lo:self._hi]

    def add(self, obs: Observation, sonars: np.ndarray | None = None) -> None:
        """Store this cycle's echoes (of the sonars where ``sonars`` (K,) bool is True, default
        all) and forget those older than the horizon."""
        pts = world_echoes(obs) if sonars is None else obs.sonar_hits()[echo_mask(obs) & sonars]
        now = obs.t
        cut = now - self.horizon
        lo, hi = self._lo, self._hi
        if not (self._sorted and now >= cut and (hi == lo or self._buf_t[hi - 1] <= now)):
            self._rebuild(pts, now, cut)
            return
        lo += int(self._buf_t[lo:hi].searchsorted(cut, side="left"))  # times >= cut: a suffix
        k = len(pts)
        start = slice(-self.capacity, None).indices(hi - lo + k)[0]  # as [-capacity:] would keep
        lo += start
        if k == 0:  # no echo this cycle (often, for a side sonar): only old points go
            self._lo = lo
            return
        if lo > hi:  # fewer than this cycle's echoes fit
            pts, k, lo = pts[lo - hi:], k - (lo - hi), hi
        if hi + k > len(self._buf_t):  # no room after the memory: move it to a larger buffer's front
            size = max(256, 2 * (hi - lo + k))
            buf_xy, buf_t = np.empty((size, 2)), np.empty(size)
            buf_xy[:hi - lo], buf_t[:hi - lo] = self._buf_xy[lo:hi], self._buf_t[lo:hi]
            self._buf_xy, self._buf_t = buf_xy, buf_t
            lo, hi = 0, hi - lo
        self._buf_xy[hi:hi + k] = pts
        self._buf_t[hi:hi + k] = now
        self._lo, self._hi = lo, hi + k

    def _rebuild(self, pts: np.ndarray, now: float, cut: float) -> None:
        """:meth:`add` when times are out of order (or the horizon is odd): mask everything."""
        xy = np.concatenate([self._xy, pts])
        t = np.concatenate([self._t, np.full(len(pts), now)])
        keep = t >= cut
        self._buf_xy, self._buf_t = xy[keep][-self.capacity:], t[keep][-self.capacity:]
        self._lo, self._hi = 0, len(self._buf_t)
        self._sorted = bool(np.all(self._buf_t[1:] >= self._buf_t[:-1]))

    def points(self, center: np.ndarray | None = None, radius: float = math.inf) -> np.ndarray:
        """(M, 2) remembered points, optionally only those within ``radius`` m of ``center``."""
        xy = self._xy
        if center is None or not math.isfinite(radius):
            return xy.copy()
        d = np.hypot(xy[:, 0] - center[0], xy[:, 1] - center[1])
        return xy.compress(d <= radius, axis=0)  # xy[d <= radius], at a third of its overhead

    def __len__(self) -> int:
        return self._hi - self._lo


# ----------------------------------------------------------------------------- loops
class CirclingDetector:
    """Is a wall follower circling in place, turning away from its side (issue 12)?

    At a junction of two or three obstacles with gaps of 0.57-0.66 m (Bug2 and TangentBug
    office_2, Bug2 office_13, TangentBug clutter_9 of the families) the follower alternates the
    turn on the spot away from a wall ahead with a short drive toward the next gap's mouth, whose
    corridor ahead is blocked again: it turns full circles away from its side, one every 4 s
    (1.9-5 turns in 20 s), without leaving a disc of 0.12-0.44 m (results/baselines/follow_s17).
    Following a boundary turns the robot toward its side in net (a lap round an obstacle) or not
    at all (along a wall); away from it by half a turn in a dead end, and by more only inside a
    room, over metres. :meth:`update` says True while the follower cycles of the last
    ``window_s`` seconds (consecutive ones: a pause over ``max_gap_s`` starts the watch again)
    turned at least ``min_turns`` full turns away from ``side`` in net and their positions fit
    in a disc of ``radius`` m (the half-diagonal of their bounding box). It does not wait for a
    full window: the office_2 cycle is said after 6 s, office_13's (a turn in 10 s) after 15 s,
    both before the episode's 0.2 m / 30 s rule ends the tightest cycles. It stops saying so
    when the robot leaves the disc or the turns leave the window.

    The numbers are constants, not planner parameters: a parameter would change the parameter
    set's id and with it every episode's noise stream, where the detector never fires.

    Args:
        side: LEFT (+1) or RIGHT (-1), the side the follower keeps the boundary on.
        window_s: how long back the circling is watched, s.
        min_turns: full turns (2 pi rad each) away from the side within the window.
        radius: m, the disc the positions of the window stay in.
        max_gap_s: s; cycles further apart than this are not consecutive (the planner did not
            follow in between) and the watch starts again.
    """

    def __init__(self, side: int, window_s: float = 20.0, min_turns: float = 1.5, radius: float = 0.5,
                 max_gap_s: float = 0.5) -> None:
        self.side, self.window_s, self.min_turns, self.radius = side, window_s, min_turns, radius
        self.max_gap_s = max_gap_s
        self._cycles: deque[tuple[float, float, float, float]] = deque()  # (t, x, y, turn since the previous cycle)
        self._turned = 0.0  # rad: sum of the window's turns (kept as the cycles come and go)
        self._yaw = 0.0  # heading of the last cycle, rad
        self.fired = False  # the last update's answer

    def update(self, t: float, x: float, y: float, yaw: float) -> bool:
        """Feed a follower cycle's time (s), position (m) and heading (rad); True when circling."""
        if not self._cycles or t - self._cycles[-1][0] > self.max_gap_s:
            self._cycles.clear()
            self._turned, turn = 0.0, 0.0
        else:
            turn = wrap_angle(yaw - self._yaw)
        self._yaw = yaw
        self._cycles.append((t, x, y, turn))
        self._turned += turn
        while self._cycles[0][0] < t - self.window_s:
            self._turned -= self._cycles.popleft()[3]
        self.fired = self._circled()
        return self.fired

    def _circled(self) -> bool:
        if -self.side * self._turned < self.min_turns * 2.0 * math.pi:
            return False
        xs, ys = [c[1] for c in self._cycles], [c[2] for c in self._cycles]
        return math.hypot(max(xs) - min(xs), max(ys) - min(ys)) / 2.0 <= self.radius


class LoopDetector:
    """Has the robot gone once around the boundary it follows?

    Armed at a point; fires when the robot returns within ``radius`` m of it after having
    been farther than ``2 * radius``, having travelled at least ``min_length`` m and having
    turned by at least ``min_turn`` rad in net (one way). A lap around a boundary, from
    outside or inside, turns the robot by 2 pi in net; a follower that lost the wall and came
    back the way it went turned by about pi, and is not on a lap.

    With ``side`` (LEFT/RIGHT, the side the boundary is kept on) the net turn must also be
    toward that side: a lap *round* an obstacle kept on the right turns the robot clockwise.
    A follower that spun on the spot or drifted round a pocket of free space turned the other
    way and is not on a lap round anything it could follow. (The lap inside a closed room,
    also the other way, is then not detected: the goal is outside, and the robot keeps going
    round until its time is up.)
    """

    def __init__(self, radius: float, min_length: float, min_turn: float = 1.5 * math.pi,
                 side: int | None = None) -> None:
        self.radius, self.min_length, self.min_turn = radius, min_length, min_turn
        self.side = side
        self.origin: np.ndarray | None = None
        self._left = False
        self._travel = 0.0
        self._turn = 0.0
        self._last: np.ndarray | None = None
        self._last_yaw: float | None = None

    def arm(self, xy: np.ndarray, yaw: float) -> None:
        self.origin = np.asarray(xy, dtype=float).copy()
        self._left, self._travel, self._turn = False, 0.0, 0.0
        self._last, self._last_yaw = self.origin.copy(), float(yaw)

    def disarm(self) -> None:
        self.origin = None

    def update(self, xy: np.ndarray, yaw: float) -> bool:
        """Feed the current position (m) and heading (rad); True when a full lap is detected."""
        if self.origin is None:
            return False
        xy = np.asarray(xy, dtype=float)
        if self._last is not None:
            self._travel += float(np.hypot(*(xy - self._last)))
        if self._last_yaw is not None:
            self._turn += wrap_angle(float(yaw) - self._last_yaw)
        self._last, self._last_yaw = xy.copy(), float(yaw)
        d = float(np.hypot(*(xy - self.origin)))
        if d > 2 * self.radius:
            self._left = True
        turn = abs(self._turn) if self.side is None else self.side * self._turn
        return self._left and d < self.radius and self._travel >= self.min_length and turn >= self.min_turn
