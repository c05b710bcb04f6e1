"""Which parts of a grid's occupied cells the sonars have seen through: the carving D* Lite's
follower measures its clearance against and VFH+ builds its histogram from.

The shared occupancy grid (:class:`~nav_bench.mapping.occupancy.OccupancyGrid`) blames a
whole echo arc and needs many readings to free a cell again, so it stands up to a cell proud
of obstacles and narrows a 0.55-0.6 m gap to ~0.4 m. The readings themselves tell which parts
of those cells are free: a cone sonar's range says everything nearer inside its cone is.
:class:`SeeThroughCarving` keeps, per occupied cell near the robot, ``CARVE_SUB`` x
``CARVE_SUB`` parts (small squares of side ``cell / CARVE_SUB``) and drops those seen through
(:func:`~nav_bench.planners.footprint.seen_through_cells`) from two different views, or under
the body, in the last ``CARVE_MEMORY_S``. The grid itself is not changed (EO/PC read it with
the paper's semantics). Units: m, s, rad.

Two ways to compute the same records (``kernel``): the NumPy code here, the reference and the
fallback, and its compiled twin :func:`nav_bench.planners.carving_kernels.carve_cells` (Numba,
the optional ``fast`` extra; used when it can be imported), equal bit for bit
(tests/planners/test_carving_kernels.py).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from types import ModuleType
from typing import NamedTuple

import numpy as np

from nav_bench import compiled
from nav_bench.errors import InputError
from nav_bench.interface import Observation, RobotInfo, SonarInfo
from nav_bench.mapping.grid import GridFrame
from nav_bench.planners.footprint import (
    CARVE_MARGIN,
    CARVE_SUB,
    PointObstacles,
    _Mounts,
    _part_offsets,
    cell_parts,
    load_carving_kernels,
    pose_floats,
    seen_through_cells,
)

VIEW_MOVE_M, VIEW_TURN_RAD = 0.03, math.radians(5.0)  # a new view for carving: moved or turned this much
CARVE_MEMORY_S = 3.0  # s: a part seen through this recently stays carved
UNDO_MODES = ("off", "axis", "unexplained")  # SeeThroughCarving's ``undo``
UNDO_REACH_M = 0.9  # m: echoes read this near or nearer may undo carvings (their arcs lie in VFH+'s 1.2 m window)
PARTS = CARVE_SUB * CARVE_SUB  # parts per cell
INF = math.inf


load_kernels = load_carving_kernels  # the carving kernels' module, or None without Numba


@dataclass(frozen=True)
class CarvedCells:
    """The occupied cells one :meth:`SeeThroughCarving.update` looked at, in the order given.

    Attributes:
        centres: (M, 2) cell centres, m.
        parts: (M, PARTS, 2) centres of each cell's parts (side ``cell / CARVE_SUB``), m.
        kept: (M, PARTS) bool: the part is not carved (not seen through from two views, nor
            under the body, in the carving's last ``memory_s``).
    """

    centres: np.ndarray
    parts: np.ndarray
    kept: np.ndarray
    kept_xy: np.ndarray | None = None  # the kept parts' centres when the kernel has them

    def kept_parts(self) -> np.ndarray:
        """(K, 2) centres of the kept parts, cell by cell, m."""
        return self.parts[self.kept] if self.kept_xy is None else self.kept_xy


class SeeThroughCarving:
    """Per-part records of what the sonars saw through, for one grid (``frame``).

    State, per cell and part (arrays (H, W, PARTS), the grid's rows and columns):
    ``carved_t`` when the part was last known free (s, ``-inf``: never), ``seen_t`` when a
    sonar last saw through it and ``seen_view`` from which view (-1: never); ``noted`` (H, W)
    the cells whose records may be set. A view is a pose: it changes when the robot has moved
    ``VIEW_MOVE_M`` or turned ``VIEW_TURN_RAD`` since the last one.

    A part counts as seen through once two readings from different views saw through it: a
    box corner can poke between the rays of one cone (a cone's rays are a few degrees apart)
    and a ray grazing past it reads long, but not from two views. Remembered a few seconds,
    so that the obstacles do not flicker with the robot's heading; a cell the grid frees
    forgets it.

    ``kernel``: ``numpy`` (this class's code), ``numba`` (the compiled twin; an
    :class:`~nav_bench.errors.InputError` without Numba) or ``auto`` (numba when it can be
    imported): the same records and masks bit for bit.

    Four settings (their defaults are D* Lite's, the carving before VFH+ kept its parts longer):

    * ``memory_s`` (s, ``CARVE_MEMORY_S``): how long a carved part stays carved. The two views
      that confirm a part must still fall within ``CARVE_MEMORY_S`` of each other.
    * ``undo`` (``UNDO_MODES``): when an echo keeps carved parts again (not those this reading
      sees through). A carving can be wrong (odometry drift; the body pressed on an obstacle),
      and a longer memory keeps a wrong carving as long as a right one; an echo says a surface
      is there. ``off``: never. ``axis``: the parts on a sonar's axis at the range read
      (:func:`echo_axis_parts`); a cone's echo comes from its nearest surface anywhere in the
      cone, and the axis point lies on it only where the sonar faces it. ``unexplained``: the
      parts on an echo's arc when none of the arc's parts is kept, so nothing the carving keeps
      explains the echo (:func:`unexplained_echo_parts`; echoes up to ``UNDO_REACH_M``).
    * ``body_clear`` (m, 0: always): the parts under the body are carved only while no sonar
      reads an echo nearer than this. Pressed on an obstacle the wheels slip, odometry drives
      on into it and the body would carve the obstacle itself; an echo that near is the sign.
    * ``body_memory_s`` (s, None: ``memory_s``): how long the body's carving lasts. Where the
      body stood is known only by odometry, and pressed on an obstacle odometry drifts into it,
      so its carving may be wrong where a view's is not.
    """

    def __init__(self, frame: GridFrame, pose: np.ndarray, kernel: str = "auto",
                 memory_s: float = CARVE_MEMORY_S, undo: str = "off", body_clear: float = 0.0,
                 body_memory_s: float | None = None) -> None:
        if undo not in UNDO_MODES:
            raise InputError(f"carving undo must be one of {list(UNDO_MODES)}, got {undo!r}")
        self.compiled = compiled.use_kernels(kernel, load_kernels, "carving")
        if self.compiled:
            _load_compiled_code()
        self.frame = frame
        self.memory_s, self.undo, self.body_clear = memory_s, undo, body_clear
        # s: the body's carving is recorded this much earlier than it happens, so that it
        # expires after body_memory_s (0: recorded at the reading's time, as a view's)
        self.body_lag = 0.0 if body_memory_s is None else max(memory_s - body_memory_s, 0.0)
        parts = (*frame.shape, PARTS)
        self.carved_t = np.full(parts, -INF, dtype=np.float32)
        self.seen_t = np.full(parts, -INF, dtype=np.float32)
        self.seen_view = np.full(parts, -1, dtype=np.int32)
        self.noted = np.zeros(frame.shape, dtype=bool)
        self.view, self.view_pose = 0, pose_floats(pose)  # (x, y, yaw) of the view, m and rad
        self._setup_of: RobotInfo | None = None  # the robot the kernel's constants are for

    def update(self, obs: Observation, rows: np.ndarray, cols: np.ndarray,
               box: tuple[int, int, int, int], occupied_box: np.ndarray) -> CarvedCells:
        """Note this cycle's reading and return the parts of the occupied cells (``rows``,
        ``cols``: (M,) grid indices, all inside ``box``) that are kept.

        ``box`` = (row0, row1, col0, col1): the grid's rectangle looked at this cycle;
        ``occupied_box`` (row1 - row0, col1 - col0) bool, which of its cells are occupied now:
        a noted cell in the box that is no longer occupied forgets its records."""
        self._next_view(pose_floats(obs.pose))
        body = self._body_carves(obs.ranges)
        if self.compiled:
            return self._update_compiled(obs, rows, cols, box, occupied_box, body)
        a0, a1, b0, b1 = box
        self._forget(a0, a1, b0, b1, occupied_box)
        # the records as one row of parts per cell, read and written by flat cell index (a
        # gather of whole rows costs less than indexing by row and column)
        flat = rows * self.frame.cols + cols
        self.noted.reshape(-1)[flat] = True
        centres = self._centres(rows, cols)
        parts = cell_parts(centres, self.frame.cell)  # (M, PARTS, 2)
        seen = self._note(obs, flat, centres, parts, body)
        carved_rows = self.carved_t.reshape(-1, PARTS)
        kept = carved_rows[flat] < obs.t - self.memory_s
        if self.undo == "unexplained":
            undo = unexplained_echo_parts(parts, kept, np.asarray(obs.pose, dtype=float),
                                          np.asarray(obs.ranges, dtype=float), obs.robot.sonar, self.frame.cell)
            undo &= ~seen
            if undo.any():
                times = carved_rows[flat]
                times[undo] = -INF
                carved_rows[flat] = times
                kept |= undo
        return CarvedCells(centres, parts, kept)

    def _body_carves(self, ranges: np.ndarray) -> bool:
        """Whether the body carves the parts under it this cycle: no sonar reads an echo nearer
        than ``body_clear`` (m; ``ranges`` (S,) m)."""
        return self.body_clear <= 0.0 or not bool(np.any(np.asarray(ranges, dtype=float) < self.body_clear))

    def _update_compiled(self, obs: Observation, rows: np.ndarray, cols: np.ndarray,
                         box: tuple[int, int, int, int], occupied_box: np.ndarray, body: bool) -> CarvedCells:
        """:meth:`update` after the view, by :func:`~nav_bench.planners.carving_kernels.carve_cells`."""
        kernels: ModuleType = load_kernels()  # type: ignore[assignment]  # looked up, not kept: pickles
        rows, cols = np.asarray(rows, dtype=np.int64), np.asarray(cols, dtype=np.int64)
        m = len(rows)
        centres, parts, kept = np.empty((m, 2)), np.empty((m, PARTS, 2)), np.empty((m, PARTS), dtype=bool)
        kept_xy = np.empty((m * PARTS, 2))
        x, y, yaw = pose_floats(obs.pose)
        reading = np.array([x, y, yaw, math.cos(yaw), math.sin(yaw), obs.t, _as_compared(obs.t - CARVE_MEMORY_S),
                            _as_compared(obs.t - self.memory_s), float(body), float(UNDO_MODES.index(self.undo)),
                            obs.t - self.body_lag, _as_compared(obs.t - self.body_lag)])
        offsets, angles, setup = self._setup(obs.robot)
        k = kernels.carve_cells(self.carved_t, self.seen_t, self.seen_view, self.noted, box[0], box[2],
                                occupied_box, rows, cols, _part_offsets(float(self.frame.cell)), offsets, angles,
                                _floats(obs.ranges), setup, reading, self.view, centres, parts, kept, kept_xy)
        return CarvedCells(centres, parts, kept, kept_xy[:k])

    def _setup(self, robot: RobotInfo) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The sonars' offsets (S, 2) m and angles (S,) rad, and the kernel's constants
        (:func:`~nav_bench.planners.carving_kernels.carve_cells`' ``setup``) for ``robot``,
        computed once per robot (its geometry is fixed for an episode)."""
        if self._setup_of is not robot:
            f, sonar = self.frame, robot.sonar
            part = f.cell / CARVE_SUB
            setup = np.array([f.xmin, f.ymin, f.cell, sonar.max_range, math.cos(sonar.cone / 2), sonar.cone / 2,
                              part * math.sqrt(0.5), math.sqrt(2.0) * (f.cell - part) / 2, robot.radius,
                              robot.radius + f.cell * 0.75, *_axis_tolerances(f.cell), UNDO_REACH_M])
            self._setup_of, self._setup_arrays = robot, (_floats(sonar.offsets), _floats(sonar.angles), setup)
        return self._setup_arrays

    def _next_view(self, pose: tuple[float, float, float]) -> None:
        x, y, yaw = pose
        vx, vy, vyaw = self.view_pose
        if (np.hypot(x - vx, y - vy) >= VIEW_MOVE_M
                or abs(math.remainder(yaw - vyaw, 2 * math.pi)) >= VIEW_TURN_RAD):
            self.view += 1
            self.view_pose = pose

    def _forget(self, a0: int, a1: int, b0: int, b1: int, occupied_box: np.ndarray) -> None:
        """A cell the grid frees forgets its carving (cells never noted hold none)."""
        noted = self.noted[a0:a1, b0:b1]
        forget = noted & ~occupied_box
        if forget.any():
            self.carved_t[a0:a1, b0:b1][forget] = -INF
            self.seen_t[a0:a1, b0:b1][forget] = -INF
            self.seen_view[a0:a1, b0:b1][forget] = -1
            noted[forget] = False

    def _centres(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """(M, 2) cell centres, m, as the grid's ``cell_center`` computes them."""
        f = self.frame
        centres = np.empty((len(rows), 2))
        centres[:, 0] = f.xmin + (cols.astype(float) + 0.5) * f.cell
        centres[:, 1] = f.ymin + (rows.astype(float) + 0.5) * f.cell
        return centres

    def _note(self, obs: Observation, flat: np.ndarray, centres: np.ndarray, parts: np.ndarray,
              body: bool) -> np.ndarray:
        """Record the parts this reading saw through, confirm those seen from another view
        within ``CARVE_MEMORY_S``, keep again the parts on an echo's axis (``undo`` axis), and
        carve the parts under the body (it stands there) when ``body``; returns which parts
        this reading saw through, (M, PARTS) bool."""
        pose = np.asarray(obs.pose, dtype=float)
        x, y, _ = pose_floats(pose)
        ranges = np.asarray(obs.ranges, dtype=float)
        seen = seen_through_cells(centres, self.frame.cell, pose, ranges, obs.robot.sonar, parts=parts)
        # only cells with a part seen through, on an echo's axis or under the body change their
        # records (a part is at most cell / sqrt 2 from its cell's centre)
        change = seen.any(axis=1)
        if body:
            change |= (np.hypot(centres[:, 0] - x, centres[:, 1] - y)
                       <= obs.robot.radius + self.frame.cell * 0.75)
        echoed = (echo_axis_parts(parts, pose, ranges, obs.robot.sonar, self.frame.cell)
                  if self.undo == "axis" else None)
        if echoed is not None:
            change |= echoed.any(axis=1)
        act = np.flatnonzero(change)
        if len(act) == 0:
            return seen
        carved_rows = self.carved_t.reshape(-1, PARTS)
        seen_rows, view_rows = self.seen_t.reshape(-1, PARTS), self.seen_view.reshape(-1, PARTS)
        at, seen_act = flat[act], seen[act]
        times, seen_at, views = carved_rows[at], seen_rows[at], view_rows[at]  # copies
        confirmed = seen_act & (views >= 0) & (views != self.view) & (seen_at >= obs.t - CARVE_MEMORY_S)
        times[confirmed] = obs.t
        if echoed is not None:
            times[echoed[act] & ~seen_act] = -INF  # a surface on the axis: whatever carved it was wrong
        seen_at[seen_act] = obs.t
        views[seen_act] = self.view
        if body:
            pa = parts[act]
            body_t = obs.t - self.body_lag  # never earlier than the part's record (a view's carving lasts)
            times[(np.hypot(pa[..., 0] - x, pa[..., 1] - y) <= obs.robot.radius) & (times < body_t)] = body_t
        carved_rows[at], seen_rows[at], view_rows[at] = times, seen_at, views
        return seen


def _axis_tolerances(cell: float) -> tuple[float, float]:
    """How near an echo's axis point a part (side ``cell / CARVE_SUB``) must lie to be on it, m:
    across the axis, half the part's diagonal (the ray passes through the part); along it, that
    plus ``CARVE_MARGIN`` (the sonar's noise)."""
    corner = cell / CARVE_SUB * math.sqrt(0.5)
    return corner, corner + CARVE_MARGIN


class _PartsFromSonars(NamedTuple):
    """One reading's sonars (``mounts``) and the parts seen from them: each sonar's axis
    direction (``ax``, ``ay``, (S, 1)) and each part's offset from each mount (``dx``, ``dy``,
    (S, K) m: a row per sonar, the K = M x PARTS parts flattened)."""

    mounts: _Mounts
    ax: np.ndarray
    ay: np.ndarray
    dx: np.ndarray
    dy: np.ndarray

    @staticmethod
    def of(parts: np.ndarray, pose: np.ndarray, ranges: np.ndarray, sonar: SonarInfo) -> _PartsFromSonars:
        """``parts`` (M, PARTS, 2) centres, m; ``pose`` (3,); ``ranges`` (S,) m."""
        mounts = _Mounts.of(pose, ranges, sonar)
        angle = mounts.yaw + sonar.angles
        q = parts.reshape(-1, 2)
        return _PartsFromSonars(mounts, np.cos(angle)[:, None], np.sin(angle)[:, None],
                                q[None, :, 0] - mounts.mx[:, None], q[None, :, 1] - mounts.my[:, None])


def echo_axis_parts(parts: np.ndarray, pose: np.ndarray, ranges: np.ndarray, sonar: SonarInfo,
                    cell: float) -> np.ndarray:
    """(M, PARTS) bool: the parts (centres ``parts`` (M, PARTS, 2), m, cells of side ``cell``)
    on one reading's echo axis points: for a sonar with an echo (range under ``max_range``),
    within :func:`_axis_tolerances` of the point on its axis at the range read. An echo comes
    from the nearest surface anywhere in the cone; only where the sonar faces that surface
    does the axis point lie on it (elsewhere it lies in the open, where no occupied part is)."""
    mounts, ax, ay, dx, dy = _PartsFromSonars.of(parts, pose, ranges, sonar)
    across_tol, along_tol = _axis_tolerances(cell)
    along = dx * ax + dy * ay
    across = np.abs(dx * ay - dy * ax)
    hit = (across <= across_tol) & (np.abs(along - mounts.r[:, None]) <= along_tol)
    hit &= (mounts.r < sonar.max_range)[:, None]
    return np.logical_or.reduce(hit, axis=0).reshape(parts.shape[:2])


def unexplained_echo_parts(parts: np.ndarray, kept: np.ndarray, pose: np.ndarray, ranges: np.ndarray,
                           sonar: SonarInfo, cell: float) -> np.ndarray:
    """(M, PARTS) bool: the parts (centres ``parts`` (M, PARTS, 2), m, cells of side ``cell``) on
    the arc of an echo that no kept part (``kept`` (M, PARTS)) explains: for each sonar with an
    echo up to ``UNDO_REACH_M``, the parts inside its cone within the along-axis tolerance of
    :func:`_axis_tolerances` of the range read; if none of them is kept, all of them.

    An echo comes from the nearest surface in the cone. Beside a gap a grazing echo comes from
    the jamb, whose surface parts no view sees through: kept, they explain it, and the proud
    parts the arc crosses stay carved. An echo that only carved parts could have returned says
    that a carving was wrong (odometry drift, the body pressed on the obstacle). Every sonar's
    test reads ``kept`` as given (before any of these parts is kept again)."""
    mounts, ax, ay, dx, dy = _PartsFromSonars.of(parts, pose, ranges, sonar)
    _, along_tol = _axis_tolerances(cell)
    d = np.hypot(dx, dy)
    on_arc = (dx * ax + dy * ay >= d * math.cos(sonar.cone / 2)) & (np.abs(d - mounts.r[:, None]) <= along_tol)
    on_arc &= ((mounts.r < sonar.max_range) & (mounts.r <= UNDO_REACH_M))[:, None]
    explained = (on_arc & kept.reshape(1, -1)).any(axis=1)
    return np.logical_or.reduce(on_arc & ~explained[:, None], axis=0).reshape(parts.shape[:2])


def _floats(values: np.ndarray) -> np.ndarray:
    """``values`` as a C-ordered float64 array (no copy when it is one): the layout the kernels
    are warmed up with."""
    return np.ascontiguousarray(values, dtype=float)


def _as_compared(limit: float) -> float:
    """``limit`` (s) as NumPy compares it with the float32 records: a Python float is rounded
    to float32 (NEP 50's weak scalar), a NumPy float64 kept; either way exactly the value a
    float64 comparison in the kernel must use."""
    return float(np.result_type(np.float32, limit).type(limit))


@functools.cache
def _load_compiled_code() -> None:
    """Call the kernels once, on a 3 x 3 grid, so that Numba loads their machine code from its
    cache (or compiles it) while the planner is set up, once per process, not in the first
    control cycle; with a C-ordered and a strided box (VFH+ passes one, D* Lite the other), and
    the clearance against the kept parts (:class:`~nav_bench.planners.footprint.PointObstacles`)."""
    frame = GridFrame(0.0, 0.0, 0.1, 3, 3)
    carving = SeeThroughCarving(frame, np.zeros(3), kernel="numpy")
    carving.compiled = True  # (a "numba" carving would call this function again)
    sonar = SonarInfo(angles=np.zeros(1), offsets=np.zeros((1, 2)), cone=0.4, min_range=0.05, max_range=3.0)
    robot = RobotInfo(radius=0.1, wheel_base=0.2, v_max=0.5, omega_max=2.0, sonar=sonar)
    obs = Observation(t=0.0, pose=np.zeros(3), goal=np.ones(2), ranges=np.ones(1), robot=robot,
                      bounds=(0.0, 0.0, 0.3, 0.3), dt=0.1)
    occupied = np.ones((3, 6), dtype=bool)
    for box in (occupied[:, :3].copy(), occupied[:, ::2]):
        kept = carving.update(obs, np.array([1]), np.array([1]), (0, 3, 0, 3), box).kept_parts()
    clearance = PointObstacles(kept, 0.01, 0.5, obs.bounds, compiled=True)  # D* Lite's follower's
    clearance(np.zeros((1, 2)))
    clearance(np.zeros((2, 2)))
