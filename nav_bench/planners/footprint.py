"""Checking a velocity command against the map and the sonars before it is driven.

A path follower (pure pursuit) steers toward a point ahead on the path; on its way the
robot's circular footprint may sweep over a corner the path only grazes, and a differential
drive pressed on a corner spins its wheels while odometry drives on. :func:`guard` rolls the
command out over a short horizon (constant ``v``, ``omega``, checked every ``step`` m) and
accepts it only when the footprint keeps its clearance from the obstacles along the whole
rollout (:func:`is_safe`; a robot already nearer than that, a map update having drawn its
margin round it, may move only so as to end no nearer, never below a floor). Otherwise it
tries the same curvature slower, then a fan of other curvatures at squeeze speed (the one that
gets closest to the point the follower aims at: the robot slides along a corner instead of
standing on it), then turns on the spot toward the path or toward a heading it can leave a
corner by, then, inside its margin, takes the way out that gains the most clearance. It stops
before it turns on the spot while still rolling (the drive's wheel accelerations are limited:
told to spin, it rolls on).

Exact geometry: an occupied cell is the square it covers (the obstacle's surface is somewhere
inside it), so the clearance of a point is its distance to the nearest occupied *square*
(:class:`SquareClearance`), not to a cell centre, and not the value of the cell the point
falls in. The occupancy grid stands up to a cell proud of the surfaces, though (a sonar blames
its whole arc), so the planner checks against the parts of the cells near the robot that its
sonars have not seen through (:func:`seen_through`, :func:`carve`, :class:`PointObstacles`):
a cone sonar's range says everything nearer inside the cone is free. The clearance required
grows with speed: ``required`` (the robot radius plus a small squeeze margin) at
``squeeze_speed`` and below, ``cruise_extra`` more at ``v_max``: the robot passes a gap only a
few cm wider than itself, slowly.

Sonar echoes: an echo says a surface lies at that range somewhere on the sonar's arc (on one
of its rays; nothing nearer inside the cone). The guard refuses a motion when the whole arc
(sampled on ``ARC_RAYS`` rays, edges included) would come within the footprint, getting
closer: the surface is in the way wherever on the arc it is. When only part of the arc is in
the way the map decides. Units: m, s, rad.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from types import ModuleType

import numpy as np
from scipy.spatial import cKDTree

from nav_bench import compiled as compiled_code
from nav_bench.errors import InputError
from nav_bench.interface import Command, Observation, SonarInfo, wrap_angle
from nav_bench.planners.follow import echo_mask, limit

Clearance = Callable[[np.ndarray], np.ndarray]
ARC_RAYS = 7  # points sampled on an echo's arc (a sonar's rays, the cone's edges included)
ECHO_MARGIN = 0.02  # m: an echo arc this close to the footprint's edge blocks the motion
ECHO_AHEAD = 0.05  # m: echoes are checked this much beyond the rollout's end (stopping room)


class SquareClearance:
    """Exact distance (m) from points to the nearest occupied cell of a grid, each cell taken
    as the square it covers.

    Args:
        occupied: (H, W) bool, row 0 at ``y0``, column 0 at ``x0`` (read, not copied: a map
            updated in place is seen by later calls).
        x0, y0: the grid's lower-left corner, m. cell: side of a cell, m.
        cap: distances beyond this are reported as ``cap`` (only cells within ``cap`` of the
            points' bounding box are searched).
    Points outside the grid get 0 (the grid covers the world; outside is no place to drive).
    """

    def __init__(self, occupied: np.ndarray, x0: float, y0: float, cell: float, cap: float) -> None:
        self.occupied, self.x0, self.y0, self.cell, self.cap = occupied, x0, y0, cell, cap

    def __call__(self, xy: np.ndarray) -> np.ndarray:
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        occ, cell = self.occupied, self.cell
        h, w = occ.shape
        u = (xy[:, 0] - self.x0) / cell  # continuous column coordinate; cell c spans [c, c + 1)
        v = (xy[:, 1] - self.y0) / cell
        inside = (u >= 0) & (u < w) & (v >= 0) & (v < h)
        out = np.full(len(xy), float(self.cap))
        if len(xy) and inside.any():
            k = self.cap / cell + 1.0
            c0, c1 = max(int(np.floor(u.min() - k)), 0), min(int(np.ceil(u.max() + k)) + 1, w)
            r0, r1 = max(int(np.floor(v.min() - k)), 0), min(int(np.ceil(v.max() + k)) + 1, h)
            rr, cc = np.nonzero(occ[r0:r1, c0:c1]) if r1 > r0 and c1 > c0 else ((), ())
            if len(rr):
                dx = np.maximum(np.abs(u[:, None] - (cc[None, :] + c0 + 0.5)) - 0.5, 0.0)
                dy = np.maximum(np.abs(v[:, None] - (rr[None, :] + r0 + 0.5)) - 0.5, 0.0)
                out = np.minimum(np.hypot(dx, dy).min(axis=1) * cell, self.cap)
        return np.where(inside, out, 0.0)


class PointObstacles:
    """Distance (m) from points to the nearest of a set of small squares (side ``2 * half``,
    the parts of occupied cells near the robot the sonars have not seen through), capped at
    ``cap``; points outside ``bounds`` (x0, y0, x1, y1) get 0. Each square counts as the disc
    round it (radius ``half * sqrt 2``): at most 0.6 cm conservative with 2 cm squares.

    A guard asks a few dozen points a cycle of a few hundred squares, and a new set of squares
    every cycle: every point against every square near it (``sqrt(dx*dx + dy*dy)``, the sum a
    k-d tree makes, so the distances are the same bit for bit) is cheaper than building a tree;
    one is built only for a large query.

    Args:
        centres: (M, 2) square centres, m.
        compiled: the direct distances by Numba kernels
            (:func:`nav_bench.planners.carving_kernels.nearest`, ``nearest_one``: the same sums
            and minima, the same distances bit for bit), as the carving that made the squares;
            an :class:`~nav_bench.errors.InputError` without Numba.
    """

    BRUTE_PAIRS = 40000  # point-square pairs up to which distances are computed directly

    def __init__(self, centres: np.ndarray, half: float, cap: float,
                 bounds: tuple[float, float, float, float], compiled: bool = False) -> None:
        self.centres = np.ascontiguousarray(np.asarray(centres, dtype=float).reshape(-1, 2))
        self.radius, self.cap, self.bounds = half * math.sqrt(2.0), cap, bounds
        self._cx, self._cy = self.centres[:, 0], self.centres[:, 1]
        self._tree: cKDTree | None = None
        if compiled and load_carving_kernels() is None:
            raise InputError("compiled clearance needs Numba: pip install 'nav-bench[fast]'")
        self.compiled = compiled

    def __call__(self, xy: np.ndarray) -> np.ndarray:
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        if len(xy) == 1 and len(self.centres):
            return np.array([self._one(*xy[0].tolist())])
        x0, y0, x1, y1 = self.bounds
        box = (xy.min(axis=0).tolist(), xy.max(axis=0).tolist()) if len(xy) else None
        if box is not None and x0 <= box[0][0] and box[1][0] < x1 and y0 <= box[0][1] and box[1][1] < y1:
            inside = None  # every point (a rollout near the robot, as a rule)
        else:
            inside = (xy[:, 0] >= x0) & (xy[:, 0] < x1) & (xy[:, 1] >= y0) & (xy[:, 1] < y1)
        if len(self.centres) == 0:
            d = np.full(len(xy), float(self.cap))
        else:
            d = self._nearest(xy, self.cap + self.radius, box)
            d = np.minimum(np.maximum(d - self.radius, 0.0), self.cap)
        return d if inside is None else np.where(inside, d, 0.0)

    def _one(self, x: float, y: float) -> float:
        """:meth:`__call__` of one point (the guard asks for the robot's own clearance every
        cycle): the same squares and sum over every centre in a few array operations (centres
        outside the filter :meth:`_nearest` applies are beyond the bound either way), the rest
        in Python floats (the same IEEE operations)."""
        x0, y0, x1, y1 = self.bounds
        if not (x0 <= x < x1 and y0 <= y < y1):
            return 0.0
        if self.compiled:
            d2 = float(load_carving_kernels().nearest_one(x, y, self.centres))  # type: ignore[union-attr]
        else:
            dx, dy = x - self._cx, y - self._cy
            d2 = float((dx * dx + dy * dy).min())
        bound = self.cap + self.radius
        if d2 >= bound * bound:
            return self.cap
        return min(max(math.sqrt(d2) - self.radius, 0.0), self.cap)

    def _nearest(self, xy: np.ndarray, bound: float,
                 box: tuple[list[float], list[float]] | None = None) -> np.ndarray:
        """(N,) distance (m) from each point to the nearest centre, ``inf`` beyond ``bound``.
        ``box``: the points' ((x, y) min, (x, y) max) when the caller has them."""
        cx, cy = self._cx, self._cy
        if len(xy) * len(cx) > self.BRUTE_PAIRS:
            if self._tree is None:
                self._tree = cKDTree(self.centres)
            return self._tree.query(xy, distance_upper_bound=bound)[0]
        if len(xy) == 0:
            return np.zeros(0)
        reach = bound + 1e-9  # centres farther along x or y than this are beyond the bound
        (xmin, ymin), (xmax, ymax) = box or (xy.min(axis=0).tolist(), xy.max(axis=0).tolist())
        if self.compiled:
            return load_carving_kernels().nearest(  # type: ignore[union-attr]
                np.ascontiguousarray(xy), self.centres, float(bound), np.array([xmin, ymin, xmax, ymax]))
        near = (cx >= xmin - reach) & (cx <= xmax + reach) & (cy >= ymin - reach) & (cy <= ymax + reach)
        if not near.any():
            return np.full(len(xy), math.inf)
        dx = xy[:, 0, None] - cx[near][None, :]
        dy = xy[:, 1, None] - cy[near][None, :]
        d2 = (dx * dx + dy * dy).min(axis=1)
        d2[d2 >= bound * bound] = math.inf  # as the tree compares: squared, the bound excluded
        return np.sqrt(d2)


def load_carving_kernels() -> ModuleType | None:
    """:mod:`nav_bench.planners.carving_kernels`, or None when Numba cannot be imported
    (:func:`nav_bench.compiled.load`); the carving's ``load_kernels`` too (carving imports this
    module, so the lookup lives here)."""
    return compiled_code.load("nav_bench.planners.carving_kernels")


def pose_floats(pose: np.ndarray) -> tuple[float, float, float]:
    """(x, y, yaw) of a pose, m and rad, as Python floats: the same values, and arithmetic on
    them is the same IEEE operations as on float64 arrays, with less overhead per call (keep
    NumPy for ``cos``, ``sin``, ``hypot``: Python's may round differently in the last bit)."""
    x, y, yaw = np.asarray(pose, dtype=float)[:3].tolist()
    return x, y, yaw


CARVE_SUB = 5  # an occupied cell is checked as CARVE_SUB x CARVE_SUB small squares
CARVE_MARGIN = 0.02  # m: a small square must lie this much nearer than a reading to be seen through


def cell_parts(centres: np.ndarray, cell: float) -> np.ndarray:
    """(M, CARVE_SUB ** 2, 2) centres of the small squares (side ``cell / CARVE_SUB``) the cells
    centred at ``centres`` (M, 2), side ``cell``, are checked as, m."""
    c = np.asarray(centres, dtype=float).reshape(-1, 2)
    return c[:, None, :] + _part_offsets(float(cell))[None, :, :]


@lru_cache(maxsize=8)
def _part_offsets(cell: float) -> np.ndarray:
    """(CARVE_SUB ** 2, 2) offsets (m) of a cell's small squares from its centre (read-only;
    the same every cycle, so computed once per cell size)."""
    offs = ((np.arange(CARVE_SUB) + 0.5) / CARVE_SUB - 0.5) * cell
    ox, oy = np.meshgrid(offs, offs)
    table = np.stack([ox.ravel(), oy.ravel()], axis=1)
    table.flags.writeable = False
    return table


def seen_through(points: np.ndarray, part: float, readings: list[tuple[np.ndarray, np.ndarray]],
                 sonar: SonarInfo, body: float = 0.0) -> np.ndarray:
    """(K,) bool: which small squares (centres ``points`` (K, 2), side ``part``, m) one of
    ``readings`` ((pose, ranges) pairs) saw through, or a reading's body covered.

    A cone sonar reports its nearest echo, so everything inside its cone nearer than the range
    read is free (without an echo: nearer than ``max_range``); a small square whose far corner
    is ``CARVE_MARGIN`` nearer than that (sonar noise) is seen through. A square whose centre
    lies within ``body`` (m, the robot radius) of a reading's pose is free too: the body stood
    there (no sonar looks inside the ring of mounts)."""
    q = np.asarray(points, dtype=float).reshape(-1, 2)
    free = np.zeros(len(q), dtype=bool)
    if len(q) == 0:
        return free
    for pose, ranges in readings:
        mounts = _Mounts.of(pose, ranges, sonar)
        free |= mounts.see_through(q[:, 0], q[:, 1], part, sonar)
        if body > 0.0:
            free |= np.hypot(q[:, 0] - mounts.x, q[:, 1] - mounts.y) <= body
    return free


@dataclass(frozen=True)
class _Mounts:
    """One reading's sonars in the world: the pose (``x``, ``y`` m, ``yaw`` rad), the ranges
    capped at ``max_range`` (``r``, (S,) m; no echo: ``max_range``) and the mounts' positions
    (``mx``, ``my``, (S,) m)."""

    x: float
    y: float
    yaw: float
    r: np.ndarray
    mx: np.ndarray
    my: np.ndarray

    @staticmethod
    def of(pose: np.ndarray, ranges: np.ndarray, sonar: SonarInfo) -> _Mounts:
        x, y, yaw = pose_floats(pose)
        cy, sy = math.cos(yaw), math.sin(yaw)
        r = np.where(np.isfinite(ranges), np.minimum(ranges, sonar.max_range), sonar.max_range)
        mx, my = sonar.mounts(x, y, cy, sy)
        return _Mounts(x, y, yaw, r, mx, my)

    def see_through(self, qx: np.ndarray, qy: np.ndarray, part: float, sonar: SonarInfo) -> np.ndarray:
        """(K,) bool: which small squares (centres ``qx``, ``qy`` (K,), side ``part``, m) one
        of the cones sees through (:func:`seen_through`, the body aside): every sonar against
        every square, :meth:`see_through_pairs` with one row per sonar."""
        every = np.arange(len(sonar.angles))
        shape = (len(every), len(qx))
        # (S, K): the reduction over sonars ORs whole rows (a reduction over a short last axis
        # is several times slower; the values are the same)
        inside = self.see_through_pairs(np.broadcast_to(qx, shape), np.broadcast_to(qy, shape), every,
                                        part, sonar)
        return np.logical_or.reduce(inside, axis=0)

    def see_through_pairs(self, qx: np.ndarray, qy: np.ndarray, sonars: np.ndarray, part: float,
                          sonar: SonarInfo) -> np.ndarray:
        """(N, P) bool: does sonar ``sonars[i]`` see through small square ``j`` (centres ``qx``,
        ``qy`` (N, P), side ``part``, m)? The square lies within the cone's half angle and its
        far corner nearer than the reading less ``CARVE_MARGIN``."""
        ax, ay = np.cos(self.yaw + sonar.angles), np.sin(self.yaw + sonar.angles)
        dx = qx - self.mx.take(sonars)[:, None]
        dy = qy - self.my.take(sonars)[:, None]
        d = np.hypot(dx, dy)
        inside = dx * ax.take(sonars)[:, None] + dy * ay.take(sonars)[:, None] >= d * math.cos(sonar.cone / 2)
        inside &= d + part * math.sqrt(0.5) <= (self.r - CARVE_MARGIN).take(sonars)[:, None]
        return inside


def seen_through_cells(centres: np.ndarray, cell: float, pose: np.ndarray, ranges: np.ndarray,
                       sonar: SonarInfo, parts: np.ndarray | None = None) -> np.ndarray:
    """(M, CARVE_SUB ** 2) bool: :func:`seen_through` of the parts (:func:`cell_parts`) of the
    cells centred at ``centres`` (M, 2), side ``cell``, m, for one reading (``pose``, ``ranges``),
    the same values bit for bit, computed only for the cells that may have a part seen through.

    A cell is skipped when, for every sonar, its parts all lie farther than the range allows
    (the part nearest the mount is at least the centre's distance less ``reach``, the parts'
    farthest offset from the centre) or all outside the cone (the disc of radius ``reach``
    round the centre lies outside it: the centre's angle off the axis exceeds half the cone
    plus ``asin(reach / distance)``). Both bounds are loosened by 1e-6 (m, rad) so that
    rounding cannot skip a cell the part test would pass. ``parts``: the cells' parts
    (:func:`cell_parts` of ``centres``) when the caller has them already."""
    c = np.asarray(centres, dtype=float).reshape(-1, 2)
    out = np.zeros((len(c), CARVE_SUB * CARVE_SUB), dtype=bool)
    if len(c) == 0:
        return out
    part = cell / CARVE_SUB
    reach = math.sqrt(2.0) * (cell - part) / 2  # centre to the farthest part centre
    mounts = _Mounts.of(pose, ranges, sonar)
    dx, dy = c[None, :, 0] - mounts.mx[:, None], c[None, :, 1] - mounts.my[:, None]
    d = np.hypot(dx, dy)  # (S, M): rows per sonar, so that the test over sonars ORs rows
    near = d - reach + part * math.sqrt(0.5) <= (mounts.r - CARVE_MARGIN + 1e-6)[:, None]
    ang = np.abs(np.arctan2(dy, dx) - (mounts.yaw + sonar.angles)[:, None])
    ang %= 2 * math.pi
    ang = np.minimum(ang, 2 * math.pi - ang)  # off the axis, [0, pi]
    spread = np.arcsin(np.minimum(reach / np.maximum(d, 1e-12), 1.0))
    facing = (d <= reach) | (ang <= sonar.cone / 2 + spread + 1e-6)
    # each cell only against the sonars that may see through it (a cell lies in the cone of
    # one or two of them): the part test costs per sonar and part (a hypot each)
    sonars, cells = np.nonzero(near & facing)
    if len(cells):
        pts = cell_parts(c[cells], cell) if parts is None else parts[cells]  # (N, PARTS, 2)
        hit, part_i = np.nonzero(mounts.see_through_pairs(pts[..., 0], pts[..., 1], sonars, part, sonar))
        out[cells[hit], part_i] = True  # OR over the sonars of a cell
    return out


def carve(centres: np.ndarray, cell: float, readings: list[tuple[np.ndarray, np.ndarray]],
          sonar: SonarInfo, body: float = 0.0) -> np.ndarray:
    """The parts of occupied cells (centres (M, 2), m, side ``cell``) that none of ``readings``
    saw through (:func:`seen_through`): (K, 2) centres of small squares of side
    ``cell / CARVE_SUB``.

    The occupancy grid marks whole cells and learns free space slowly (a cell an arc once
    blamed needs many readings through it): it stands up to a cell proud of a surface. What is
    left of a cell after the carving is where the surface can still be."""
    pts = cell_parts(centres, cell).reshape(-1, 2)
    return pts[~seen_through(pts, cell / CARVE_SUB, readings, sonar, body)]


@dataclass(frozen=True)
class GuardSettings:
    """How :func:`guard` checks a command.

    Attributes:
        required: clearance (m, robot centre to the nearest occupied cell's square) kept at
            ``squeeze_speed`` and below: the robot radius plus the squeeze margin.
        horizon: rollout length, s. steps: at least this many points are checked along it,
            and never more than ``step`` m apart.
        slow_distance: the speed falls linearly to 40 % as the clearance ahead drops from
            the required one plus ``slow_distance`` to the required one, m.
        cruise_extra: clearance required beyond ``required`` at ``v_max``, growing linearly
            from ``squeeze_speed``, m.
        squeeze_speed: the speed (m/s) at which only ``required`` is kept; also the speed of
            the fan of curvatures tried when the wanted one is not safe.
        v_max: the follower's cruise speed, m/s.
        step: the checked points of a rollout are at most this far apart, m.
        floor: clearance (m) a robot already nearer than required may dip to on its way out
            (:func:`is_safe`); None: it may not get any nearer.
    """

    required: float
    horizon: float = 1.0
    steps: int = 6
    slow_distance: float = 0.2
    cruise_extra: float = 0.0
    squeeze_speed: float = 0.1
    v_max: float = 0.4
    step: float = 0.02
    floor: float | None = None

    def required_at(self, v: float) -> float:
        """Clearance (m) required of a rollout at speed ``v`` m/s."""
        span = max(self.v_max - self.squeeze_speed, 1e-6)
        return self.required + self.cruise_extra * min(1.0, max(0.0, (abs(v) - self.squeeze_speed) / span))


def rollout(pose: np.ndarray, v: float, omega: float, horizon: float, steps: int) -> np.ndarray:
    """(steps, 2) positions, m, of a unicycle driving (v m/s, omega rad/s) from ``pose``
    (x, y, yaw) for ``horizon`` s, at ``horizon / steps`` intervals (the start excluded)."""
    t = _rollout_times(float(horizon), int(steps))
    x, y, yaw = np.asarray(pose, dtype=float)[:3].tolist()
    out = np.empty((len(t), 2))
    if abs(omega) < 1e-6:
        out[:, 0] = x + v * t * math.cos(yaw)
        out[:, 1] = y + v * t * math.sin(yaw)
        return out
    r = v / omega
    th = yaw + omega * t
    out[:, 0] = x + r * (np.sin(th) - math.sin(yaw))
    out[:, 1] = y - r * (np.cos(th) - math.cos(yaw))
    return out


@lru_cache(maxsize=64)
def _rollout_times(horizon: float, steps: int) -> np.ndarray:
    """(steps,) times (s) of a rollout's points (read-only; a few (horizon, steps) pairs recur
    every cycle, and ``linspace`` costs more than the rollout itself)."""
    t = np.linspace(horizon / steps, horizon, steps)
    t.flags.writeable = False
    return t


def rollout_steps(v: float, settings: GuardSettings) -> int:
    """Points checked along a rollout at ``v`` m/s: ``settings.steps`` or more, so that they
    are at most ``settings.step`` m apart (a corner cannot slip between two of them)."""
    return max(settings.steps, math.ceil(abs(v) * settings.horizon / max(settings.step, 1e-3)))


def echo_arcs(obs: Observation) -> np.ndarray:
    """(M, ARC_RAYS, 2) robot-frame points of each echo's arc: the echo's range along
    ``ARC_RAYS`` rays spread over the cone (edges included), from the sonar's mount, m."""
    s = obs.robot.sonar
    mask = echo_mask(obs)
    if not mask.any():
        return np.zeros((0, ARC_RAYS, 2))
    r = np.asarray(obs.ranges, dtype=float)[mask]
    ang = s.angles[mask][:, None] + _arc_spread(float(s.cone))[None, :]
    off = s.offsets[mask][:, None, :]
    unit = np.empty((*ang.shape, 2))  # (the cosines and sines computed on contiguous arrays,
    unit[:, :, 0] = np.cos(ang)  # as np.stack had them: a strided output may take another loop)
    unit[:, :, 1] = np.sin(ang)
    return off + r[:, None, None] * unit


@lru_cache(maxsize=8)
def _arc_spread(cone: float) -> np.ndarray:
    """(ARC_RAYS,) ray angles (rad) across a cone of ``cone`` rad, edges included (read-only)."""
    spread = np.linspace(-cone / 2, cone / 2, ARC_RAYS)
    spread.flags.writeable = False
    return spread


def echo_blocks(obs: Observation, v: float, omega: float, horizon: float, steps: int = 12,
                arcs: np.ndarray | None = None, yaw: float = 0.0) -> bool:
    """Would driving (``v``, ``omega``) for ``horizon`` s, after turning on the spot by ``yaw``
    rad, bring the footprint within ``ECHO_MARGIN`` of the whole arc of some echo, nearer than
    it is now? (Then the surface that echoed is in the way wherever on its arc it lies.)"""
    if v == 0.0:
        return False
    arcs = echo_arcs(obs) if arcs is None else arcs
    if len(arcs) == 0:
        return False
    pts = arcs.reshape(-1, 2)
    d_now = np.hypot(pts[:, 0], pts[:, 1])
    # the rollout stays within |v| horizon of the robot: an arc with a point farther than that
    # beyond the footprint's reach cannot be hit whole (1e-6 m: rounding)
    reach = obs.robot.radius + ECHO_MARGIN + abs(v) * horizon + 1e-6
    if not (d_now < reach).reshape(arcs.shape[:2]).all(axis=1).any():
        return False
    path = rollout(np.array([0.0, 0.0, yaw]), v, omega, horizon, steps)  # robot frame, start excluded
    d_along = np.hypot(pts[:, None, 0] - path[None, :, 0], pts[:, None, 1] - path[None, :, 1]).min(axis=1)
    hit = (d_along < obs.robot.radius + ECHO_MARGIN) & (d_along < d_now - 0.005)
    return bool(np.any(hit.reshape(arcs.shape[:2]).all(axis=1)))


SAFE_TOLERANCE = 0.002  # m: rounding allowed below the clearance a rollout must keep


def is_safe(clear_now: float, clear_along: np.ndarray, required: float, floor: float | None = None) -> bool:
    """A rollout keeps ``required`` m of clearance; or, if the robot is already closer than that,
    it ends no closer than it is now and never comes nearer than ``floor`` on the way (nor
    nearer than it is now, if that is less than ``floor``; without ``floor``: never nearer than
    now). 2 mm tolerance: with more, commands that each lose a
    little ratchet the robot onto the obstacle. The end is judged, not every point, so that a
    robot too near a corner may arc past it (a turn away first sweeps toward it)."""
    tol = SAFE_TOLERANCE
    low = float(clear_along.min()) if len(clear_along) else math.inf
    if low >= required - tol:
        return True
    if floor is None:
        return low >= min(required, clear_now) - tol
    return low >= min(floor, clear_now) - tol and float(clear_along[-1]) >= min(required, clear_now) - tol


@dataclass(frozen=True)
class Guarded:
    """The command to drive and whether the wanted one had to be changed (``blocked``: not
    even a slower version of it was safe, nor any curvature of the fan). ``escape``: the world
    heading (rad) of a way out for a robot inside its margin (:func:`_escape`), which the
    follower should hold until it is out (the command turns toward it)."""

    command: Command
    blocked: bool
    escape: float | None = None


FAN = 13  # curvatures tried at squeeze speed when the wanted one is not safe


def guard(obs: Observation, wanted: Command, toward: float, clearance: Clearance,
          settings: GuardSettings, target: np.ndarray | None = None, speed: float = 0.0) -> Guarded:
    """:func:`guard_motion`, and a stop before any turn on the spot while the robot still
    rolls faster than ``STOP_BEFORE_TURN`` (``speed``: its present forward speed, m/s, from
    odometry). A differential drive whose wheels are limited in acceleration keeps rolling
    while it is told to turn on the spot (each wheel heads for its own target, their mean
    hardly changes), and even more so when the turn flips direction each cycle: 10 cm and
    more in the baselines study, onto the corner it was turning away from."""
    out = guard_motion(obs, wanted, toward, clearance, settings, target)
    if out.command.v == 0.0 and out.command.omega != 0.0 and abs(speed) > STOP_BEFORE_TURN:
        return Guarded(Command(0.0, 0.0), out.blocked)
    return out


STOP_BEFORE_TURN = 0.03  # m/s: a robot rolling faster than this stops before it turns on the spot


def guard_motion(obs: Observation, wanted: Command, toward: float, clearance: Clearance,
                 settings: GuardSettings, target: np.ndarray | None = None) -> Guarded:
    """``wanted`` if its rollout is safe (slowed near obstacles); else the same curvature at
    1/2 speed or at squeeze speed; else the safe arc of a fan at squeeze speed whose end comes
    closest to ``target`` (world xy, m; default 1 m along the world heading ``toward``, rad),
    if it gets closer to it (the robot slides along a corner instead of standing on it); else a
    turn on the spot toward ``toward`` when the robot is more than 0.3 rad off it (the unsafe
    arcs came from driving while turning); else a turn on the spot toward a heading from which
    driving straight at squeeze speed is safe and gets closer to ``target`` (out of a corner
    that every forward arc from the present heading brushes); else, for a robot already inside
    its margin, the way out that gains the most clearance (:func:`_escape`: a map update drew
    the margin round it); else a turn on the spot toward ``toward`` (``blocked``).

    Never returns a command whose rollout brings the footprint closer to an occupied cell
    than allowed (:func:`is_safe`), nor one driving the footprint onto the whole arc of an
    echo. ``blocked`` is also set when the command is not the wanted one at a lower speed."""
    pose = np.asarray(obs.pose, dtype=float)
    clear_now = float(clearance(pose[None, :2])[0])
    err = wrap_angle(toward - float(pose[2]))
    turn = limit(0.0, 2.5 * err, obs.robot)
    if wanted.v == 0.0:
        return Guarded(wanted, False)
    arcs = echo_arcs(obs)
    s = settings
    kappa = wanted.omega / wanted.v

    def check(v: float, omega: float, start: np.ndarray = pose) -> np.ndarray | None:
        """Clearances along the rollout from ``start``, or None if it is not safe."""
        n = rollout_steps(v, s)
        along = clearance(rollout(start, v, omega, s.horizon, n))
        if not is_safe(clear_now, along, s.required_at(v), s.floor):
            return None
        yaw = float(start[2]) - float(pose[2])  # echoes are seen from the present heading
        if echo_blocks(obs, v, omega, s.horizon + ECHO_AHEAD / abs(v), min(n, 24), arcs, yaw):
            return None
        return along

    speeds = [wanted.v, 0.5 * wanted.v]
    if abs(wanted.v) > s.squeeze_speed:
        speeds.append(math.copysign(s.squeeze_speed, wanted.v))
    for i, v in enumerate(speeds):
        along = check(v, v * kappa)
        if along is not None:
            slow = (float(along.min()) - s.required_at(v)) / max(s.slow_distance, 1e-6)
            v_out = v * min(1.0, max(0.4, slow)) if v > 0 else v
            if abs(v_out) < s.squeeze_speed <= abs(v):
                v_out = math.copysign(s.squeeze_speed, v)  # not slower than squeezing needs
            return Guarded(limit(v_out, v_out * kappa, obs.robot), i > 0)
    if wanted.v < 0:
        return Guarded(turn, True)
    v = min(s.squeeze_speed, obs.robot.v_max)
    if target is None:
        target = pose[:2] + np.array([math.cos(toward), math.sin(toward)])
    slide = _fan(obs, pose, v, target, check, s)
    if slide is not None:
        return Guarded(slide, True)
    if abs(err) > 0.3 and clear_now >= s.required:
        return Guarded(turn, False)
    heading = _heading_fan(pose, v, target, check, s)
    if heading is not None:
        return Guarded(limit(0.0, 2.5 * wrap_angle(heading - float(pose[2])), obs.robot), True)
    if clear_now < s.required:
        out = _escape(obs, pose, v, clear_now, check)
        if out is not None:
            cmd = limit(v, 0.0, obs.robot) if out == float(pose[2]) else limit(
                0.0, 2.5 * wrap_angle(out - float(pose[2])), obs.robot)
            return Guarded(cmd, True, escape=out)
    return Guarded(turn, True)


ESCAPE_GAIN = 0.01  # m: an escape must end at least this much farther from the obstacles


def _escape(obs: Observation, pose: np.ndarray, v: float, clear_now: float,
            check: Callable[..., np.ndarray | None]) -> float | None:
    """For a robot inside its margin with no way on toward its target: the world heading (the
    present one first, then every 30 deg) from which driving straight at ``v`` gains the most
    clearance, at least ``ESCAPE_GAIN`` (never losing any on the way); None if none does."""
    best: tuple[float, float] | None = None
    for deg in range(0, 360, 30):
        yaw = float(pose[2]) + math.radians(deg)
        along = check(v, 0.0, np.array([pose[0], pose[1], yaw]))
        if along is None or float(np.min(along)) < clear_now - SAFE_TOLERANCE:
            continue
        gain = float(along[-1]) - clear_now
        if gain >= ESCAPE_GAIN and (best is None or gain > best[0] + 1e-9):
            best = (gain, yaw)
    return None if best is None else best[1]


HEADING_FAN_DEG = (20.0, 40.0, 60.0, 90.0, 120.0)  # turns tried by :func:`_heading_fan`, each way


def _fan(obs: Observation, pose: np.ndarray, v: float, target: np.ndarray,
         check: Callable[..., np.ndarray | None], s: GuardSettings) -> Command | None:
    """The safe arc at ``v`` (turn rates up to the robot's limit, at most 2 rad/s) whose end
    comes closest to ``target``, if it gets at least 1 cm closer to it; else None."""
    if v <= 0.0:
        return None
    w_max = min(obs.robot.omega_max, 2.0)
    d0 = float(np.hypot(*(target - pose[:2])))
    omegas = np.linspace(-w_max, w_max, FAN)
    ends = np.array([rollout(pose, v, float(w), s.horizon, 1)[-1] for w in omegas])
    d = np.hypot(target[0] - ends[:, 0], target[1] - ends[:, 1])
    for i in np.argsort(d, kind="stable"):
        if d[i] > d0 - 0.01:
            break
        if check(v, float(omegas[i])) is not None:
            return limit(v, float(omegas[i]), obs.robot)
    return None


def _heading_fan(pose: np.ndarray, v: float, target: np.ndarray,
                 check: Callable[..., np.ndarray | None], s: GuardSettings) -> float | None:
    """A world heading (rad), the nearest to the present one of ``HEADING_FAN_DEG`` each way,
    from which driving straight at ``v`` for the horizon is safe and ends at least 1 cm closer
    to ``target``; None if there is none."""
    if v <= 0.0:
        return None
    d0 = float(np.hypot(*(target - pose[:2])))
    for deg in HEADING_FAN_DEG:
        for sign in (1.0, -1.0):
            yaw = float(pose[2]) + sign * math.radians(deg)
            start = np.array([pose[0], pose[1], yaw])
            end = start[:2] + v * s.horizon * np.array([math.cos(yaw), math.sin(yaw)])
            if float(np.hypot(*(target - end))) <= d0 - 0.01 and check(v, 0.0, start) is not None:
                return yaw
    return None
