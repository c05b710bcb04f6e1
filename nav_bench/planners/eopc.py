"""EO/PC: the paper's online re-planning planner (``paper/online-replanning-paper.txt``).

Two behaviours share the robot (paper Sec. 2):

* **EO** (obstacle avoidance, :func:`eo_speed`) sets only the translation speed ``v`` from
  the front sonars: full speed beyond ``lambda1``, a linear ramp down to ``lambda2``, a stop
  below ``lambda2``.
* **PC** (path re-planning, :func:`choose_neighbour`) runs at a *breakpoint*. It scores
  ``n_neighbors`` points on a circle of radius ``RR`` around it with the occupancy grid PMO
  and the trajectory grid PMT, and commits to one, ``Pi``. The robot turns in place toward
  ``Pi`` and drives there (EO still controls ``v``).

When PC runs is ``replan_on`` (PAPER-NOTES, "When PC runs: two readings"):

* ``blocked_path`` (default): a breakpoint is (a) where EO stops the robot, or (b) the
  arrival at ``Pi`` while the straight path from there to the goal is blocked on PMO
  (:func:`goal_path_blocked`; unknown cells never block). At (a) ``theta = 0`` is the
  robot's heading, at (b) the direction of the segment just driven (previous breakpoint ->
  ``Pi``: the old path). Near obstacles the path is a chain of breakpoints ``RR`` apart,
  each chosen by F; when the line to the goal clears, the robot heads for the goal.
* ``stop``: PC runs only where EO stops the robot; after ``Pi`` the robot heads for the
  goal whatever PMO shows. A property of this reading, not of the code: in a pocket whose
  far wall lies across every line to the goal and that is deeper than about
  ``RR + lambda2``, every such line ends on that wall again, so the breakpoints cannot leave
  the pocket; PMT then only spreads them along it.

Every interpretation follows ``PAPER-NOTES.md``; where the notes leave a choice open it
is a parameter, with the reason next to it in :attr:`EOPC.params`.

The PC decision and the blocked-path check are pure functions of the grids, so they can be
tested on hand-built grids without a simulator.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from nav_bench.errors import PlannerError
from nav_bench.interface import (
    REPLAN,
    Command,
    GridState,
    Observation,
    ReplanEvent,
    SonarInfo,
    wrap_angle,
)
from nav_bench.mapping.grid import GridFrame
from nav_bench.mapping.occupancy import SONAR_MODELS, UNKNOWN, OccupancyGrid
from nav_bench.mapping.visits import VisitGrid
from nav_bench.planners.base import Param, ParamError, Planner

FREE, UNSURE, HIGH = 0, 50, 100  # the three levels of RC, RI and the risk index r
IPO_MODES = ("evidence", "raw")
REPLAN_ON = ("blocked_path", "stop")  # when PC runs (PAPER-NOTES, "When PC runs")
BLOCKED_BY = ("segment", "corridor")  # how "the path to the goal is blocked" is judged
# What made PC run, and what theta = 0 was measured from, in each ``replan`` event
TRIGGER_EO_STOP, TRIGGER_BLOCKED_PATH = "eo_stop", "blocked_path"
THETA_FROM_HEADING, THETA_FROM_OLD_PATH = "heading", "old_path"


# ============================================================================ EO: the speed rule
def front_sonars(sonar: SonarInfo, front_fov: float) -> np.ndarray:
    """(K,) bool: the sonars facing the direction of motion, ``|mount angle| <= front_fov / 2``."""
    angles = np.array([wrap_angle(float(a)) for a in sonar.angles])
    return np.abs(angles) <= front_fov / 2 + 1e-9


@dataclass(frozen=True)
class FrontSonars:
    """The front sonars' geometry, worked out once per robot for :meth:`distance`
    (:func:`front_distance`, what EO/PC asks every cycle).

    Attributes:
        index: (F,) which readings are the front sonars'.
        off_x, off_y: (F,) their mount offsets from the robot centre, m.
        cos, sin: (F,) of their mount angles.
        max_range: m, what a no-echo reading counts as.
    """

    index: np.ndarray
    off_x: np.ndarray
    off_y: np.ndarray
    cos: np.ndarray
    sin: np.ndarray
    max_range: float

    @classmethod
    def of(cls, sonar: SonarInfo, front: np.ndarray) -> FrontSonars:
        """The sonars ``front`` (K,) bool picks out of ``sonar``."""
        off = np.asarray(sonar.offsets, dtype=float)[front]
        angles = sonar.angles[front]
        return cls(np.flatnonzero(front), np.ascontiguousarray(off[:, 0]),
                   np.ascontiguousarray(off[:, 1]), np.cos(angles), np.sin(angles),
                   sonar.max_range)

    def distance(self, ranges: np.ndarray) -> float:
        """:func:`front_distance` of (K,) readings ``ranges`` (m), the same floating-point
        operations on the front sonars only."""
        if not len(self.index):
            return math.inf
        r = ranges.take(self.index)
        r = np.where(np.isfinite(r), np.minimum(r, self.max_range), self.max_range)
        ex = r * self.cos
        ex += self.off_x
        ey = np.multiply(r, self.sin, out=r)
        ey += self.off_y
        return float(np.minimum.reduce(np.hypot(ex, ey)))


def front_distance(ranges: np.ndarray, sonar: SonarInfo, front: np.ndarray) -> float:
    """Shortest distance (m) from the **robot centre** to an echo of a front sonar.

    Readings are measured from the sonar's own frame on the body edge; EO's thresholds are
    from the centre (PAPER-NOTES), so each echo point is placed in the robot frame
    (``offset + range * axis``) and its distance to the centre taken. For a sonar mounted
    radially, as on the default robot, that is exactly ``range + |offset|``.
    A no-echo reading counts as ``max_range``. ``inf`` when no sonar is in front.
    A planner asking every cycle keeps a :class:`FrontSonars` and calls its ``distance``.
    """
    return FrontSonars.of(sonar, front).distance(np.asarray(ranges, dtype=float))


def eo_speed(d: float, v_max: float, lambda1: float, lambda2: float, v_min: float = 0.0) -> float:
    """EO's translation speed (m/s) for a front distance ``d`` (m, from the robot centre).

    ``v_max`` for ``d >= lambda1``; ``0`` for ``d < lambda2``; in between the linear ramp
    ``v_max * (d - lambda2) / (lambda1 - lambda2)``, floored at ``v_min``. The floor exists
    because the pure ramp reaches 0 exactly at ``lambda2``: a robot obeying it approaches
    ``lambda2`` geometrically and never stops, so PC would never run. ``v_min = 0`` gives
    the pure ramp.
    """
    if d >= lambda1:
        return v_max
    if d < lambda2:
        return 0.0
    return min(v_max, max(v_min, v_max * (d - lambda2) / (lambda1 - lambda2)))


def steer(heading_error: float, gain: float, omega_max: float) -> float:
    """Proportional turn rate (rad/s) toward a heading error (rad), limited to ``omega_max``
    (``np.clip``'s result, NaN included, without its cost on one number)."""
    return float(min(max(gain * heading_error, -omega_max), omega_max))


# ============================================================================ PC: cost terms
def region_radius(settings: EOPC.Settings) -> float:
    """Radius (m) of region A around a neighbour: ``region_radius``, or ``RR / 2`` when it is 0."""
    return settings.region_radius or settings.RR / 2


def neighbour_points(breakpoint: np.ndarray, heading: float, radius: float,
                     n: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``n`` breakpoint neighbours and their angles.

    Returns ``(points (n, 2) m, theta (n,) rad)``; neighbour ``i`` is at
    ``theta_i = 2 pi i / n`` wrapped to (-pi, pi] relative to ``heading`` (theta = 0 along
    the old path, positive to the left), on the circle of ``radius`` around ``breakpoint``.
    """
    theta = 2 * math.pi * np.arange(n) / n
    theta = np.where(theta > math.pi + 1e-12, theta - 2 * math.pi, theta)
    bx, by = float(breakpoint[0]), float(breakpoint[1])
    pts = np.stack([bx + radius * np.cos(heading + theta), by + radius * np.sin(heading + theta)], 1)
    return pts, theta


def travel_cost(theta: np.ndarray, RR: float) -> np.ndarray:
    """CD, ``G(P) = RR * |theta|`` (m): the arc turned to face P, either way round."""
    return RR * np.abs(theta)


def heuristic_cost(points: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """CHC, ``H(P)``: Euclidean distance (m) from each of (n, 2) points to the goal."""
    return np.hypot(points[:, 0] - goal[0], points[:, 1] - goal[1])


@functools.lru_cache(maxsize=8)
def square_offsets(k: int) -> tuple[np.ndarray, np.ndarray]:
    """(row, col) offsets, ((2k+1)^2,) each, of the square of cells ``-k..k`` around a cell,
    row-major (``np.mgrid`` raveled), worked out once per size (read-only)."""
    dr, dc = np.mgrid[-k:k + 1, -k:k + 1]
    dr, dc = dr.ravel(), dc.ravel()
    dr.flags.writeable = dc.flags.writeable = False
    return dr, dc


def region_cells(frame: GridFrame, points: np.ndarray,
                 radius: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The cells of region A (a disc of ``radius`` m) around each point.

    A cell belongs to A when its centre lies within ``radius`` of the point. Returns
    ``(rows, cols, member)``, each (n, m): a square window of m cells per point, and which
    of them are in the disc. Rows/cols may lie outside the grid (see ``frame.contains``).
    """
    dr, dc = square_offsets(math.ceil(radius / frame.cell) + 1)
    rc = frame.world_to_cell(points)
    rows = rc[:, 0, None] + dr[None, :]
    cols = rc[:, 1, None] + dc[None, :]
    centres = frame.cell_center(rows, cols)
    member = np.hypot(centres[..., 0] - points[:, 0, None],
                      centres[..., 1] - points[:, 1, None]) <= radius + 1e-9
    return rows, cols, member


def region_values(grid: np.ndarray, frame: GridFrame, rows: np.ndarray, cols: np.ndarray,
                  outside: float) -> np.ndarray:
    """(n, m) float values of ``grid`` at the region cells; cells outside the grid read ``outside``.

    Only the region cells are read, so the cost does not depend on the grid's size.
    """
    inside = frame.contains(rows, cols)
    v = np.full(rows.shape, float(outside))
    v[inside] = grid[rows[inside], cols[inside]]
    return v


def obstacle_evidence(pmo: np.ndarray) -> np.ndarray:
    """``max(0, PMO - 50) * 2``: 0 for free and unknown cells, 100 for certainly occupied."""
    return np.maximum(0.0, np.asarray(pmo, dtype=float) - UNKNOWN) * 2


def intensity_of_obstacles(pmo: np.ndarray, frame: GridFrame, rows: np.ndarray, cols: np.ndarray,
                           member: np.ndarray, mode: str) -> np.ndarray:
    """IPO (n,): sum over region A of obstacle evidence (``evidence``) or of PMO as stored (``raw``).

    Cells outside the grid are unknown (50): evidence 0, raw 50.
    """
    v = region_values(pmo, frame, rows, cols, float(UNKNOWN))
    if mode == "evidence":
        v = obstacle_evidence(v)
    elif mode != "raw":
        raise PlannerError(f"ipo_mode must be one of {list(IPO_MODES)}, got {mode!r}")
    return np.sum(np.where(member, v, 0.0), axis=1)


def intensity_of_trajectory(pmt: np.ndarray, frame: GridFrame, rows: np.ndarray, cols: np.ndarray,
                            member: np.ndarray) -> np.ndarray:
    """IPT (n,): sum of PMT visit counts over region A (cells outside the grid: 0)."""
    return np.sum(np.where(member, region_values(pmt, frame, rows, cols, 0.0), 0.0), axis=1)


def collision_risk(pmo_values: np.ndarray, free_below: float, occupied_above: float) -> np.ndarray:
    """RC: PMO quantised to 0 (``< free_below``), 100 (``> occupied_above``), else 50."""
    v = np.asarray(pmo_values)
    return np.where(v < free_below, FREE, np.where(v > occupied_above, HIGH, UNSURE)).astype(np.int64)


def iteration_risk(counts: np.ndarray, visits_many: int) -> np.ndarray:
    """RI: PMT quantised to 0 (never visited), 100 (``>= visits_many`` cycles), else 50."""
    c = np.asarray(counts)
    return np.where(c <= 0, FREE, np.where(c >= visits_many, HIGH, UNSURE)).astype(np.int64)


def risk_index(rc: np.ndarray, ri: np.ndarray) -> np.ndarray:
    """Table 1 of the paper, which is exactly ``r = max(RC, RI)``."""
    return np.maximum(rc, ri)


def point_risks(pmo: np.ndarray, pmt: np.ndarray, frame: GridFrame, points: np.ndarray,
                settings: EOPC.Settings) -> tuple[np.ndarray, np.ndarray]:
    """(RC, RI) of each point's own cell. A point outside the grid gets RC 100 (beyond the map)."""
    rc_idx = frame.world_to_cell(points)
    inside = frame.contains(rc_idx[:, 0], rc_idx[:, 1])
    r, c = rc_idx[inside, 0], rc_idx[inside, 1]
    rc = np.full(len(points), HIGH, dtype=np.int64)
    ri = np.zeros(len(points), dtype=np.int64)
    rc[inside] = collision_risk(pmo[r, c], settings.free_below, settings.occupied_above)
    ri[inside] = iteration_risk(pmt[r, c], settings.visits_many)
    return rc, ri


def blocked_segments(pmo: np.ndarray, frame: GridFrame, start: np.ndarray, points: np.ndarray,
                     occupied_above: float) -> np.ndarray:
    """(n,) True where the segment start -> point crosses a cell with RC = 100 (or leaves the grid).

    The segment is sampled every quarter cell. The start cell itself is skipped: the robot
    stands in it, so an occupied reading there is sonar noise, not a wall.
    """
    steps = max(2, math.ceil(4 * float(np.max(np.hypot(*(points - start).T), initial=0.0)) / frame.cell))
    t = np.arange(1, steps + 1) / steps
    samples = start[None, None, :] + t[None, :, None] * (points - start)[:, None, :]
    rc = frame.world_to_cell(samples)
    rows, cols = rc[..., 0], rc[..., 1]
    inside = frame.contains(rows, cols)
    own_row, own_col = frame.cell_of(float(start[0]), float(start[1]))  # world_to_cell in floats
    own = (rows == own_row) & (cols == own_col)
    occupied = np.zeros(rows.shape, dtype=bool)
    occupied[inside] = pmo[rows[inside], cols[inside]] > occupied_above
    return np.any((occupied | ~inside) & ~own, axis=1)


def crossed_cells(frame: GridFrame, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """(N, 2) row, col of every cell the segment ``start -> end`` (m) passes through, in order.

    Exact (a supercover but for cells touched only at a corner): the segment is cut where it
    crosses a grid line and each piece's midpoint names its cell, so a segment of length L
    costs about ``L / cell * 2`` points whatever the grid's size. Cells may lie outside the
    grid (see ``frame.contains``).
    """
    start, end = np.asarray(start, dtype=float)[:2], np.asarray(end, dtype=float)[:2]
    x0, y0 = frame.bounds[0], frame.bounds[1]
    cuts = [np.array([0.0, 1.0])]
    for axis, origin in ((0, x0), (1, y0)):
        a, b = start[axis], end[axis]
        if abs(b - a) > 1e-12:
            lo, hi = sorted(((a - origin) / frame.cell, (b - origin) / frame.cell))
            lines = np.arange(math.floor(lo) + 1, math.ceil(hi)) * frame.cell + origin
            cuts.append((lines - a) / (b - a))
    t = np.sort(np.concatenate(cuts))
    t = t[np.append(True, t[1:] != t[:-1])]  # np.unique's result, without its wrappers
    mid = (t[:-1] + t[1:]) / 2
    cols = np.floor((start[0] + mid * (end[0] - start[0]) - x0) / frame.cell).astype(np.int64)
    rows = np.floor((start[1] + mid * (end[1] - start[1]) - y0) / frame.cell).astype(np.int64)
    return np.stack([rows, cols], axis=1)


def goal_path_blocked(pmo: np.ndarray, frame: GridFrame, start: np.ndarray, goal: np.ndarray,
                      occupied_above: float, half_width: float = 0.0) -> bool:
    """Is the straight path ``start -> goal`` blocked on PMO (any crossed cell with RC = 100)?

    ``half_width`` 0 judges the cells the segment itself crosses (:func:`crossed_cells`);
    ``half_width > 0`` judges a corridor that wide on each side (the robot's radius for
    ``blocked_by: corridor``): the cells crossed by parallel lines at most half a cell apart
    across it. Unknown cells and cells outside the grid never block (the freespace
    assumption, as in D* Lite). The start cell is skipped: the robot stands in it, so an
    occupied reading there is sonar noise.

    Args:
        pmo: (H, W) occupancy 0..100. start, goal: (2,) m. occupied_above: RC = 100 above
            this. half_width: m.
    """
    start = np.asarray(start, dtype=float)[:2]
    goal = np.asarray(goal, dtype=float)[:2]
    delta = goal - start
    length = math.hypot(delta[0], delta[1])
    if half_width > 0 and length > 0:
        lanes = max(3, 2 * math.ceil(half_width / (frame.cell / 2)) + 1)
        normal = np.array([-delta[1], delta[0]]) / length
        cells = np.concatenate([crossed_cells(frame, start + o * normal, goal + o * normal)
                                for o in np.linspace(-half_width, half_width, lanes)])
    else:
        cells = crossed_cells(frame, start, goal)
    rows, cols = cells[:, 0], cells[:, 1]
    height, width = pmo.shape
    inside = (rows >= 0) & (rows < height) & (cols >= 0) & (cols < width)
    rows, cols = rows[inside], cols[inside]
    own_row, own_col = frame.cell_of(float(start[0]), float(start[1]))  # world_to_cell in floats
    occupied = (pmo[rows, cols] > occupied_above) & ~((rows == own_row) & (cols == own_col))
    return bool(occupied.any())


def old_path_heading(previous_breakpoint: np.ndarray | None, point: np.ndarray,
                     fallback: float) -> float:
    """Direction (rad) of the segment just driven, ``previous_breakpoint -> point``: the "old
    path" that ``theta = 0`` follows at a blocked-path breakpoint. ``fallback`` (the robot's
    heading) when there is no previous breakpoint or the two points coincide.
    """
    if previous_breakpoint is None:
        return fallback
    dx, dy = (np.asarray(point, dtype=float)[:2] - np.asarray(previous_breakpoint, dtype=float)[:2])
    if math.hypot(dx, dy) < 1e-9:
        return fallback
    return math.atan2(dy, dx)


def term_scales(settings: EOPC.Settings, breakpoint: np.ndarray, goal: np.ndarray,
                region_size: np.ndarray) -> dict[str, np.ndarray | float]:
    """Largest possible value of each cost term (what ``normalize`` divides by).

    * G: ``RR * pi`` (a neighbour straight behind).
    * H: ``|breakpoint - goal| + RR``, the farthest any neighbour of this breakpoint can be.
    * IPO: ``|A| * 100``, every cell of region A certainly occupied (both ``ipo_mode``\\ s).
    * IPT: ``|A| * visits_many``, every cell of A visited "too often". PMT counts are
      unbounded, so this is the saturation scale of RI rather than a hard maximum: the
      normalised IPT can exceed 1 in heavily revisited places.
    * r: 100.

    ``|A|`` is the number of cells of each neighbour's own region (n,), at least 1.
    """
    size = np.maximum(region_size, 1)
    return {
        "G": settings.RR * math.pi,
        "H": max(float(np.hypot(*(np.asarray(goal) - breakpoint))) + settings.RR, 1e-9),
        "IPO": size * 100.0,
        "IPT": size * float(max(settings.visits_many, 1)),
        "r": float(HIGH),
    }


def select_neighbour(r: np.ndarray, rc: np.ndarray, ri: np.ndarray, F: np.ndarray,
                     candidate: np.ndarray, beta_I: int, fallback: np.ndarray,
                     force: bool) -> tuple[int | None, int]:
    """The paper's re-planning rules then its threshold algorithm (PAPER-NOTES "Choosing").

    1. candidates with ``r == 0``: smallest F;
    2. else candidates with ``RC < beta_I``: smallest RI, ties by F (taken even when that
       RI is still ``>= alpha_I``: the paper accepts a high iteration risk in extreme cases);
    3. else blocked: ``(None, 3)``, unless ``force``: then the smallest F among the
       candidates, or if there are none among ``fallback``, or if none among all.

    Remaining ties go to the lowest index (theta = 0, then +22.5 deg, ...: left first).
    Returns ``(index or None, tier)``.
    """
    safe = candidate & (r == FREE)
    if safe.any():
        return int(np.flatnonzero(safe)[np.argmin(F[safe])]), 1
    ok = np.flatnonzero(candidate & (rc < beta_I))
    if ok.size:
        order = np.lexsort((F[ok], ri[ok]))  # primary key RI, then F
        return int(ok[order[0]]), 2
    if not force:
        return None, 3
    pool = candidate if candidate.any() else fallback if fallback.any() else np.ones_like(candidate)
    idx = np.flatnonzero(pool)
    return int(idx[np.argmin(F[idx])]), 3


@dataclass(frozen=True)
class Decision:
    """One PC activation: every neighbour's terms and the choice.

    Arrays are (n,), one entry per neighbour, in the order of :func:`neighbour_points`.
    ``G, H, IPO, IPT`` are the raw terms (m, m, PMO sum, visit count sum); ``F`` the
    weighted (and, with ``normalize``, scaled) cost. ``chosen`` is None when PC is blocked
    (tier 3 without force): the robot keeps its heading this cycle.
    """

    breakpoint: np.ndarray
    heading: float
    points: np.ndarray
    theta: np.ndarray
    G: np.ndarray
    H: np.ndarray
    IPO: np.ndarray
    IPT: np.ndarray
    RC: np.ndarray
    RI: np.ndarray
    r: np.ndarray
    F: np.ndarray
    segment_blocked: np.ndarray
    tried: np.ndarray
    candidate: np.ndarray
    chosen: int | None
    tier: int
    forced: bool

    @property
    def turn(self) -> float:
        """Y, the turn in place (rad, CCW +) from the breakpoint heading to the chosen point."""
        return 0.0 if self.chosen is None else float(self.theta[self.chosen])

    @property
    def target(self) -> np.ndarray | None:
        """The chosen point Pi (2,), m, or None."""
        return None if self.chosen is None else self.points[self.chosen]

    def replan_event(self, t: float, trigger: str, theta_from: str, **extra: Any) -> ReplanEvent:
        """The decision as a :class:`~nav_bench.interface.ReplanEvent` (numbers rounded to 1e-6,
        the cost terms and risks among its details); ``extra`` goes into the details too."""
        def f(a: np.ndarray) -> list[float]:
            return [round(v, 6) for v in a.tolist()]  # tolist: Python floats, one conversion

        bx, by = f(self.breakpoint)
        return ReplanEvent(
            t=t, breakpoint=(bx, by), neighbours=tuple((round(x, 6), round(y, 6)) for x, y in self.points.tolist()),
            risk=tuple(self.r.tolist()), candidate=tuple(self.candidate.tolist()),
            chosen=self.chosen, trigger=trigger, theta_from=theta_from,
            details={"heading": round(float(self.heading), 6), "theta": f(self.theta),
                     "rc": self.RC.tolist(), "ri": self.RI.tolist(),
                     "G": f(self.G), "H": f(self.H), "IPO": f(self.IPO), "IPT": f(self.IPT),
                     "F": f(self.F), "tier": self.tier, "forced": self.forced, **extra})


def choose_neighbour(pmo: np.ndarray, pmt: np.ndarray, frame: GridFrame, breakpoint: np.ndarray,
                     heading: float, goal: np.ndarray, settings: EOPC.Settings,
                     tried: Sequence[np.ndarray] = (), force: bool = False) -> Decision:
    """PC, steps 1.4-1.9 of the paper's global algorithm: score the neighbours, pick one.

    Args:
        pmo: (H, W) uint8 occupancy 0..100 (50 unknown). pmt: (H, W) int visit counts.
        frame: the grids' geometry (both grids share it).
        breakpoint: (2,) where EO stopped the robot, m. heading: robot yaw there, rad.
        goal: (2,) m.
        settings: the planner's settings (weights, thresholds, radii).
        tried: points (m) already chosen from this same breakpoint without the robot
            getting anywhere; neighbours within half a neighbour spacing of one are not
            candidates (they lead back into the same stop).
        force: tier 3 may not wait any longer: take the smallest F anyway.

    A neighbour is a *candidate* unless it was ``tried`` or (with
    ``exclude_blocked_segments``) the segment to it crosses a cell with RC = 100.
    """
    bp = np.asarray(breakpoint, dtype=float)[:2]
    goal = np.asarray(goal, dtype=float)[:2]
    points, theta = neighbour_points(bp, heading, settings.RR, settings.n_neighbors)
    G = travel_cost(theta, settings.RR)
    H = heuristic_cost(points, goal)
    rows, cols, member = region_cells(frame, points, region_radius(settings))
    IPO = intensity_of_obstacles(pmo, frame, rows, cols, member, settings.ipo_mode)
    IPT = intensity_of_trajectory(pmt, frame, rows, cols, member)
    rc, ri = point_risks(pmo, pmt, frame, points, settings)
    r = risk_index(rc, ri)
    if settings.normalize:
        s = term_scales(settings, bp, goal, member.sum(axis=1))
    else:
        s = {"G": 1.0, "H": 1.0, "IPO": 1.0, "IPT": 1.0, "r": 1.0}
    F = (settings.w_g * G / s["G"] + settings.w_h * H / s["H"] + settings.w_ipo * IPO / s["IPO"]
         + settings.w_ipt * IPT / s["IPT"] + settings.w_r * r / s["r"])
    if settings.exclude_blocked_segments:
        seg = blocked_segments(pmo, frame, bp, points, settings.occupied_above)
    else:
        seg = np.zeros(len(points), dtype=bool)
    was_tried = np.zeros(len(points), dtype=bool)
    if len(tried):
        spacing = 2 * settings.RR * math.sin(math.pi / settings.n_neighbors)
        t = np.asarray(tried, dtype=float).reshape(-1, 2)
        gap = np.hypot(points[:, None, 0] - t[None, :, 0], points[:, None, 1] - t[None, :, 1])
        was_tried = np.any(gap < spacing / 2, axis=1)
    candidate = ~seg & ~was_tried
    chosen, tier = select_neighbour(r, rc, ri, F, candidate, settings.beta_I, ~was_tried, force)
    return Decision(bp, float(heading), points, theta, G, H, IPO, IPT, rc, ri, r, F, seg,
                    was_tried, candidate, chosen, tier, bool(force and tier == 3 and chosen is not None))


# ============================================================================ the planner
class EOPC(Planner):
    """The paper's EO/PC planner (see the module docstring and PAPER-NOTES.md).

    Modes: ``goal`` (drive toward the goal), ``turn`` (turn in place by Y toward Pi),
    ``to_point`` (drive toward Pi), ``at_point`` (arrived at Pi with the path to the goal
    blocked: PC is due; only with ``replan_on: blocked_path``). Per control cycle (paper's
    global algorithm): update PMO and PMT (step 1.1) -> goal reached? (1.2) -> at a
    breakpoint (EO stopped the robot, or Pi reached with the goal path blocked)? then PC
    (1.3-1.9) -> EO speed (2) -> command (3).

    Each ``replan`` event carries ``trigger`` (``eo_stop`` or ``blocked_path``) and
    ``theta_from`` (``heading`` or ``old_path``) with ``heading`` the direction (rad) that
    ``theta = 0`` points to.

    A stop right where the previous re-plan was made (within ``retry_radius``: the robot
    turned toward Pi but EO still sees something closer than ``lambda2``) is a new
    breakpoint and a new re-plan, but the points already tried from that spot are not
    candidates, so the planner cannot loop on one zero-motion choice: each retry turns to
    a different point, at most ``n_neighbors`` of them. When none is left, PC is blocked
    (tier 3): it waits ``max_blocked_cycles`` cycles, then takes the smallest F among the
    untried neighbours, or among all of them if every one has been tried.
    """

    name = "eopc"
    reference = ("Path Planning Algorithm for Initially Unknown Indoor Environment Navigation "
                 "(EO/PC), read with PAPER-NOTES.md")
    params = (
        # -- EO: speed from the front sonars
        Param("v_max", 0.5, "m/s", "top translation speed EO commands (the robot's own limit also applies)",
              minimum=0.0),
        Param("v_min", 0.05, "m/s", "floor of EO's ramp between lambda1 and lambda2; the pure ramp "
              "(0) never lets the robot reach lambda2, so PC would never run", minimum=0.0),
        Param("omega_max", 1.0, "rad/s", "turn-rate limit of every rotation (the robot's own limit also applies)",
              minimum=0.0),
        Param("front_fov_deg", 100.0, "deg", "sonars with |mount angle| <= front_fov/2 give EO's front distance",
              minimum=0.0, maximum=360.0),
        Param("lambda1", 0.8, "m", "EO slows down below this front distance (from the robot centre)",
              minimum=0.0),
        Param("lambda2", 0.35, "m", "EO stops below this front distance (from the robot centre); "
              "the stop is a breakpoint", minimum=0.0),
        # -- motion toward the goal / Pi (the paper gives the turn Y, not a controller)
        Param("k_heading", 2.0, "1/s", "proportional gain from heading error to turn rate, while driving "
              "toward the goal or Pi and while turning in place", minimum=0.0),
        Param("align_deg", 60.0, "deg", "heading errors above this are first turned in place (v = 0, EO "
              "not consulted); below it v = EO's v * cos(error)", minimum=0.0, maximum=180.0),
        Param("turn_tolerance_deg", 3.0, "deg", "the in-place turn by Y is done when within this of Y "
              "(turn counted from odometry)", minimum=0.0),
        Param("goal_tolerance", 0.2, "m", "goal reached (robot stops) within this distance (step 1.2)",
              minimum=0.0),
        Param("waypoint_tolerance", 0.15, "m", "Pi reached within this distance; then head for the goal "
              "again", minimum=0.0),
        # -- PC: neighbours and cost terms
        Param("RR", 0.5, "m", "radius of the circle of breakpoint neighbours", minimum=0.01),
        Param("n_neighbors", 16, "-", "neighbours on the circle, evenly spaced from theta = 0 (the heading)",
              minimum=1),
        Param("region_radius", 0.0, "m", "radius of region A for IPO and IPT; 0 means RR/2", minimum=0.0),
        Param("free_below", 35.0, "%", "RC = 0 (free) when PMO < this; two free sonar sightings of an "
              "unknown cell (40, 31) make it free", minimum=0.0, maximum=100.0),
        Param("occupied_above", 65.0, "%", "RC = 100 (occupied) when PMO > this; one echo on an unknown "
              "cell (70) makes it occupied", minimum=0.0, maximum=100.0),
        Param("visits_many", 20, "cycles", "RI = 100 (too often visited) at this many control cycles "
              "in a cell; RI = 50 from 1", minimum=1),
        Param("alpha_I", 100, "risk", "RI threshold: a tier-2 choice with RI >= alpha_I is still taken "
              "(flagged in the event)", minimum=0, maximum=100),
        Param("beta_I", 100, "risk", "RC threshold: tier 2 considers neighbours with RC < beta_I",
              minimum=0, maximum=100),
        Param("max_blocked_cycles", 5, "cycles", "control cycles PC waits with every neighbour at r = 100 "
              "before taking the smallest F anyway", minimum=0),
        Param("w_g", 1.0, "-", "weight of CD, G = RR*|theta| in F", minimum=0.0),
        Param("w_h", 1.0, "-", "weight of CHC, H = distance to the goal in F", minimum=0.0),
        Param("w_ipo", 1.0, "-", "weight of IPO (obstacle intensity over A) in F", minimum=0.0),
        Param("w_ipt", 1.0, "-", "weight of IPT (trajectory intensity over A) in F", minimum=0.0),
        Param("w_r", 1.0, "-", "weight of the risk index r in F", minimum=0.0),
        Param("normalize", False, "-", "divide each term of F by its largest possible value before "
              "weighting (see eopc.term_scales); false adds them raw as the paper does"),
        Param("ipo_mode", "evidence", "-", "IPO sums obstacle evidence max(0, PMO-50)*2 ('evidence') or "
              "PMO as stored ('raw', unknown cells count 50)", choices=IPO_MODES),
        Param("exclude_blocked_segments", True, "-", "a neighbour whose segment from the breakpoint "
              "crosses an RC = 100 cell is not a candidate (the robot could not drive there)"),
        Param("replan_on", "blocked_path", "-", "when PC runs: 'blocked_path' where EO stops the robot "
              "and on arriving at Pi while the straight path to the goal is blocked on PMO (theta = 0 "
              "along the segment just driven); 'stop' only where EO stops the robot, heading for the goal "
              "after every Pi (PAPER-NOTES, 'When PC runs')", choices=REPLAN_ON),
        Param("blocked_by", "segment", "-", "how 'the path to the goal is blocked' is judged: 'segment' "
              "the PMO cells along the line Pi -> goal, 'corridor' the cells within the robot's radius of "
              "it; only RC = 100 cells block, unknown cells never do", choices=BLOCKED_BY),
        Param("retry_radius", 0.1, "m", "a stop within this of the previous breakpoint is the same spot: "
              "points already tried there are not candidates (no zero-motion loops)", minimum=0.0),
        # -- the grids (PMO sensor model, PMT)
        Param("cell", 0.1, "m", "cell side of PMO and PMT (the paper's lambda)", minimum=0.01),
        Param("map_margin", 0.2, "m", "the grids cover the world bounds plus this margin, so boundary "
              "walls (just outside the world) are mapped too", minimum=0.0),
        Param("l_occ", 0.85, "log-odds", "added to PMO cells at a sonar echo arc (> 0; one echo: PMO 70)",
              minimum=0.0),
        Param("l_free", -0.4, "log-odds", "added to PMO cells a sonar saw through (< 0; once: PMO 40)",
              maximum=0.0),
        Param("l_min", -2.0, "log-odds", "lower clamp of PMO log-odds (PMO 12): keeps the map able "
              "to change", maximum=0.0),
        Param("l_max", 3.5, "log-odds", "upper clamp of PMO log-odds (PMO 97)", minimum=0.0),
        Param("hit_thickness", 0.1, "m", "radial thickness of the echo arc marked occupied (one cell)",
              minimum=0.001),
        Param("sonar_model", "elfes", "-", "PMO's inverse sensor model (nav_bench.mapping.occupancy): "
              "'elfes' weighs by angle from the axis and shares the echo over its arc; 'band' adds "
              "l_occ to the whole arc (before issue 12)", choices=SONAR_MODELS),
    )

    @classmethod
    def check_rules(cls, p: dict[str, Any]) -> None:
        if p["lambda1"] <= p["lambda2"]:
            raise ParamError(f"eopc needs lambda1 > lambda2, got {p['lambda1']} and "
                             f"{p['lambda2']}", "lambda1")
        if p["free_below"] > p["occupied_above"]:
            raise ParamError("eopc needs free_below <= occupied_above, got "
                             f"{p['free_below']} and {p['occupied_above']}", "free_below")

    # -- episode state -----------------------------------------------------------------------
    def reset(self, obs: Observation, rng: np.random.Generator) -> None:
        super().reset(obs, rng)
        p = self.settings
        sonar = obs.robot.sonar
        front = front_sonars(sonar, math.radians(p.front_fov_deg))
        if not front.any():
            raise PlannerError(f"eopc: no sonar within front_fov_deg = {p.front_fov_deg} "
                               f"(mount angles {np.degrees(sonar.angles).round(1).tolist()} deg)")
        self._front = FrontSonars.of(sonar, front)
        m = p.map_margin
        xmin, ymin, xmax, ymax = obs.bounds
        bounds = (xmin - m, ymin - m, xmax + m, ymax + m)
        self.pmo = OccupancyGrid(bounds, p.cell, model=p.sonar_model, l_occ=p.l_occ, l_free=p.l_free,
                                 l_min=p.l_min, l_max=p.l_max, hit_thickness=p.hit_thickness)
        self.pmt = VisitGrid(bounds, p.cell)
        self._v_max = min(p.v_max, obs.robot.v_max)
        self._omega_max = min(p.omega_max, obs.robot.omega_max)
        self._goal = np.asarray(obs.goal, dtype=float)[:2].copy()
        self.mode = "goal"
        self._target: np.ndarray | None = None  # Pi
        self._turn_goal = 0.0  # Y, rad
        self._turned = 0.0  # turn done so far, summed from odometry
        self._last_yaw = float(obs.pose[2])
        self._spot: np.ndarray | None = None  # first breakpoint of the current stopping spot
        self._tried: list[np.ndarray] = []
        self._blocked = 0
        self._reached = False
        self._breakpoint: np.ndarray | None = None
        self._chain_from: np.ndarray | None = None  # the breakpoint the current Pi was chosen at
        self._corridor = obs.robot.radius if p.blocked_by == "corridor" else 0.0

    def act(self, obs: Observation) -> Command:
        p = self.settings
        pose = np.asarray(obs.pose, dtype=float)
        x, y, yaw = float(pose[0]), float(pose[1]), float(pose[2])
        # Step 1.1: the grids, every cycle, before anything else
        self.pmo.update(pose, obs.ranges, obs.robot.sonar)
        self.pmt.add(pose[:2])
        # Step 1.2: goal reached -> stop
        if math.hypot(self._goal[0] - x, self._goal[1] - y) < p.goal_tolerance:
            if not self._reached:
                self._reached = True
                self.emit("goal_reached", obs.t, position=[x, y])
            self.mode = "goal"
            return Command(0.0, 0.0)
        self._reached = False
        if self.mode == "turn":
            self._turned += wrap_angle(yaw - self._last_yaw)
            self._last_yaw = yaw
            remaining = self._turn_goal - self._turned
            if abs(remaining) > math.radians(p.turn_tolerance_deg):
                return Command(0.0, steer(remaining, p.k_heading, self._omega_max))
            self.mode = "to_point"
        if self.mode == "to_point":
            assert self._target is not None
            if math.hypot(self._target[0] - x, self._target[1] - y) <= p.waypoint_tolerance:
                self.mode = "at_point" if self._goal_path_blocked(pose) else "goal"
        if self.mode == "at_point":  # breakpoint (b): Pi reached, the straight path is blocked
            assert self._target is not None
            old_path = old_path_heading(self._chain_from, self._target, yaw)
            return self._replan(obs, pose, TRIGGER_BLOCKED_PATH, old_path)
        target = self._target if self.mode == "to_point" and self._target is not None else self._goal
        error = wrap_angle(math.atan2(target[1] - y, target[0] - x) - yaw)
        if abs(error) > math.radians(p.align_deg):
            # a pure rotation: no translation is wanted, so EO (a speed rule) has nothing to stop
            return Command(0.0, steer(error, p.k_heading, self._omega_max))
        d = self._front.distance(np.asarray(obs.ranges, dtype=float))
        if d < p.lambda2:  # Step 1.3: EO has stopped the robot -> PC
            return self._replan(obs, pose, TRIGGER_EO_STOP, yaw)
        v = eo_speed(d, self._v_max, p.lambda1, p.lambda2, p.v_min)  # Step 2
        return Command(v * math.cos(error), steer(error, p.k_heading, self._omega_max))

    def _goal_path_blocked(self, pose: np.ndarray) -> bool:
        """At the arrival at Pi: is the straight path to the goal blocked on PMO? Always False
        with ``replan_on: stop`` (the robot then heads for the goal whatever PMO shows)."""
        if self.settings.replan_on != "blocked_path":
            return False
        return goal_path_blocked(self.pmo.values(copy=False), self.pmo.frame, pose[:2], self._goal,
                                 self.settings.occupied_above, self._corridor)

    def _replan(self, obs: Observation, pose: np.ndarray, trigger: str, theta_zero: float) -> Command:
        """Steps 1.4-1.10 at a breakpoint: score neighbours, commit to Pi, start turning by Y.

        ``trigger`` is what made PC run (``eo_stop`` or ``blocked_path``); ``theta_zero``
        (rad) the direction theta = 0 points to: the heading at an EO stop, the old path at
        a blocked-path breakpoint.
        """
        p = self.settings
        bp = pose[:2].copy()
        yaw = float(pose[2])
        if self._spot is None or math.hypot(*(bp - self._spot)) > p.retry_radius:
            self._spot, self._tried, self._blocked = bp, [], 0  # a new spot: nothing tried here
        self._breakpoint = bp
        decision = choose_neighbour(
            self.pmo.values(copy=False), self.pmt.counts, self.pmo.frame, bp, theta_zero,
            self._goal, self.settings, tried=self._tried,
            force=self._blocked >= p.max_blocked_cycles)
        if decision.chosen is None:  # tier 3: keep the steering angle at zero, wait
            self._blocked += 1
            self.emit("blocked", obs.t, breakpoint=[float(v) for v in bp], count=self._blocked,
                      risk=[int(v) for v in decision.r], trigger=trigger)
            return Command(0.0, 0.0)
        self._blocked = 0
        theta_from = THETA_FROM_HEADING if trigger == TRIGGER_EO_STOP else THETA_FROM_OLD_PATH
        event = decision.replan_event(
            obs.t, trigger, theta_from, retry=len(self._tried),
            high_iteration_risk=bool(decision.RI[decision.chosen] >= self.settings.alpha_I))
        self.emit(REPLAN, obs.t, **event.data())
        target = decision.points[decision.chosen].copy()
        self._tried.append(target)
        self._chain_from, self._target = bp, target
        # Y: the turn from the robot's own yaw to Pi (at an EO stop theta = 0 is that yaw)
        turn = decision.turn if trigger == TRIGGER_EO_STOP else wrap_angle(theta_zero + decision.turn - yaw)
        self._turn_goal, self._turned, self._last_yaw = turn, 0.0, yaw
        self.mode = "turn"
        if abs(self._turn_goal) <= math.radians(p.turn_tolerance_deg):
            self.mode = "to_point"  # Y = 0: nothing to turn; drive (EO decides) from next cycle
            return Command(0.0, 0.0)
        return Command(0.0, steer(self._turn_goal, p.k_heading, self._omega_max))

    def debug_state(self) -> dict[str, Any]:
        if not hasattr(self, "pmo"):
            return {}
        target = (self._target if self.mode in ("turn", "to_point", "at_point") and self._target is not None
                  else self._goal)
        grids = GridState(pmo=self.pmo.values(), pmt=self.pmt.counts.copy(),
                          bounds=self.pmo.bounds, cell=self.pmo.cell)
        return {
            **grids.state(),
            "target": [float(target[0]), float(target[1])],
            "mode": self.mode,
            "breakpoint": None if self._breakpoint is None else [float(v) for v in self._breakpoint],
        }
