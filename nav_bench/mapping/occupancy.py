"""PMO, the occupancy grid the robot builds from its sonars (paper Sec. 2.1, ref. [18]).

Each cell holds the log-odds ``l = log(p / (1 - p))`` that it is occupied; ``l = 0`` is
unknown. A sonar reading ``r`` updates the cells of its cone with an inverse sensor model,
chosen by ``OccupancyGrid(model=...)`` (:data:`SONAR_MODELS`):

``"elfes"`` (the default): the Moravec & Elfes sonar model with the echo attributed across
the arc. References: H. Moravec, A. Elfes, "High resolution maps from wide angle sonar",
ICRA 1985; A. Elfes, "Using occupancy grids for mobile robot perception and navigation",
IEEE Computer 22(6), 1989; K. Konolige, "Improved occupancy grids for map building",
Autonomous Robots 4, 1997 (MURIEL).

* a sonar is most sensitive on its axis: every cell's evidence is weighted by
  ``w = 1 - (theta / (cone/2))^2`` (Elfes' angular term), ``theta`` the cell's angle from the
  axis; cells at the cone's edge get almost nothing;
* cells seen through (closer than ``r - hit_thickness/2``) get ``l += w * l_free``;
* the echo came from ONE place on the arc (``|dist - r| <= hit_thickness/2``), so the arc's
  evidence is shared, not copied (Konolige 1997: a wide arc gives each cell little
  evidence): cell ``i`` gets ``l += l_occ * min(1, echo_share * w_i p_i / sum_j w_j p_j)``
  over the arc's cells, ``p`` the current occupancy probability. A short, narrow arc gives
  its axis cell the full ``l_occ``; a long one spreads it: with the defaults a wall straight
  ahead becomes an obstacle (PMO > 65, EO/PC's and D* Lite's threshold) after 1 echo at
  0.5 m, 2 at 1 m, 3 at 2 m, 4 at 2.9 m (tests/mapping/test_sonar_model.py; 0.1 s apart at
  the default 10 Hz control rate). ``echo_share = 3`` marks walls a reading sooner but lets a
  jamb's repeated echo narrow a 1 m door by a cell on each side. Weighting by ``p`` explains
  the echo by the arc cells believed occupied: a cell other readings already saw through (low
  ``p``) takes a small part of a later echo (MURIEL's idea of not re-blaming cells known free).
  So free readings from other poses carve phantom arc cells (a door's gap marked by an echo
  from its jamb) away and they stay carved, while a real wall, which no correct reading sees
  through, keeps collecting its echoes.

``"band"``: the model before issue 12, three bands: the full ``l_occ`` on EVERY cell of
the arc and the full ``l_free`` on every cell seen through. One echo from a door's jamb
closes a 1 m door; kept for reproducing older results (EO/PC's recorded references).

Both: cells beyond the arc are untouched (nothing is known behind an obstacle); a reading at
``max_range`` (no echo) frees the cone up to ``max_range`` and marks nothing.
``l`` is clamped to ``[l_min, l_max]`` so the map can still change when the world does
(movers). :meth:`OccupancyGrid.values` gives the map as ``uint8`` 0..100 (ROS map
convention: 0 free, 50 unknown, 100 occupied) which is what the planner reads.

"In the cone" uses cell centres: a centre is inside when it lies ahead of the sonar and
its lateral distance from the sonar axis is at most ``along * tan(cone/2) + cell/2``. The
half-cell widening keeps narrow cones at short range from slipping between cell centres
(a 25 deg cone is only 0.09 m wide at 0.2 m); ``theta`` of the Elfes weight is measured on
the same widened cone (the lateral distance less half a cell), so the cell holding the axis
always has ``w`` near 1.

Speed (``benchmarks/bench_sonar_map.py``): one update touches only the cells of a disc around
the robot, precomputed once as cell offsets sorted by distance. The cones' candidate cells
(a 25 deg cone is ~1/14 of the disc) come from tables kept per grid, one per 2 deg of axis
direction, each built on first use, cut to each sonar's reach; all sonars' candidates then go
through the exact cone and range tests together, and the Konolige normalisation is computed
on the arc's cells only. The tables only pick candidates: any superset of a cone's cells, in
the disc's order, gives the same cells in the same order, so the map does not depend on the
bin width (2 deg: 3 % more candidates than 0.5 deg, a quarter of the tables to build while
the robot turns). Fusing all sonars at once equals fusing them one after the other as long as
no cell lies in two cones; a sonar whose cone shares a cell with an earlier one is fused after
it. The per-sonar values (a short Python loop over the sonars, with Python's ``math``) are
common to two ways of doing the per-cell work, chosen per grid (``OccupancyGrid(kernel=...)``):

* ``"numpy"``, the reference: a fixed number of NumPy calls on the ~600 candidates (their cost
  is mostly per call) and three transcendental functions per cell (``hypot``, the Elfes
  weight's ``arctan2``, the value's ``exp``); no Python loop over cells.
* ``"numba"`` (``"auto"`` when Numba is installed, the ``fast`` extra):
  :mod:`~nav_bench.mapping.occupancy_kernels` reads the candidates from the tables, tests
  them, finds the runs of sonars and fuses in loops over the cells, with the same IEEE
  operations in the same order; ``arctan2`` and ``exp`` stay in NumPy between the kernels
  (their last bits differ in Numba) and ``hypot`` is skipped for cells that a sum of squares
  with a 1e-9 margin proves seen through. The same log-odds and values bit for bit
  (tests/mapping/test_occupancy_kernels.py); about 0.45x the NumPy path's CPU per update
  (results/speed/sonar_kernel_s15).
"""

from __future__ import annotations

import array
import bisect
import functools
import itertools
import math
from dataclasses import dataclass
from types import ModuleType
from typing import NamedTuple

import numpy as np

from nav_bench import compiled
from nav_bench.errors import InputError
from nav_bench.interface import SonarInfo
from nav_bench.mapping.grid import Bounds, GridFrame, OnGridFrame

UNKNOWN = 50  # value of a cell never observed (log-odds 0)
SONAR_MODELS = ("elfes", "band")  # inverse sensor models, see the module docstring
_AXIS_BINS = 180  # sonar axis directions with their own table of candidate cells (2 deg)
_AXIS_BIN = 2 * math.pi / _AXIS_BINS  # rad


def log_odds_to_values(log_odds: np.ndarray) -> np.ndarray:
    """Occupancy percent 0..100 (uint8, rounded) of log-odds (any shape)."""
    return np.rint(100.0 / (1.0 + np.exp(-log_odds))).astype(np.uint8)


class OccupancyGrid(OnGridFrame):
    """A fixed-size log-odds occupancy grid updated from ray-cone sonars.

    Args:
        bounds: (xmin, ymin, xmax, ymax) in m; the grid covers at least this rectangle.
        cell: cell side, m (the paper's lambda, 0.1 m).
        model: inverse sensor model, one of :data:`SONAR_MODELS` (module docstring).
        l_occ: log-odds added at the echo arc (> 0): to every arc cell ("band"), to the arc's
            most likely cell and shared out to the others ("elfes").
        l_free: log-odds added to a cell seen through (< 0), times the angular weight
            ("elfes").
        l_min, l_max: clamp of the log-odds (l_min < 0 < l_max).
        hit_thickness: radial thickness of the echo arc, m (default: one cell).
        echo_share: "elfes" only: an arc cell gets at most this many cells' share of the echo
            (``s_i = min(1, echo_share * w_i p_i / sum_j w_j p_j)``, module docstring).
        kernel: the per-cell loops of :meth:`update`: "numpy" (the reference), "numba"
            (:mod:`~nav_bench.mapping.occupancy_kernels`, the optional ``fast`` extra; an
            :class:`~nav_bench.errors.InputError` without Numba) or "auto" (numba when it can be
            imported). Both give the same log-odds and values, bit for bit.

    Points and cells outside the grid are ignored by :meth:`update`.
    """

    def __init__(self, bounds: Bounds, cell: float = 0.1, *, model: str = "elfes",
                 l_occ: float = 0.85, l_free: float = -0.4, l_min: float = -2.0,
                 l_max: float = 3.5, hit_thickness: float | None = None,
                 echo_share: float = 2.0, kernel: str = "auto") -> None:
        if model not in SONAR_MODELS:
            raise InputError(f"unknown sonar model {model!r}; expected one of {list(SONAR_MODELS)}")
        if not echo_share > 0:
            raise InputError(f"echo_share must be > 0 cells, got {echo_share!r}")
        self.model = model
        self.echo_share = float(echo_share)
        if not (l_occ > 0 > l_free):
            raise InputError(f"occupancy grid needs l_occ > 0 > l_free, got {l_occ!r}, {l_free!r}")
        if not (l_min < 0 < l_max):
            raise InputError(f"occupancy grid needs l_min < 0 < l_max, got {l_min!r}, {l_max!r}")
        self.frame = GridFrame.from_bounds(bounds, cell)
        self.l_occ, self.l_free = float(l_occ), float(l_free)
        self.l_min, self.l_max = float(l_min), float(l_max)
        self.hit_thickness = float(hit_thickness) if hit_thickness else self.frame.cell
        if self.hit_thickness <= 0:
            raise InputError(f"hit_thickness must be > 0 m, got {hit_thickness!r}")
        self._log_odds = np.zeros(self.frame.shape, dtype=np.float64)
        self._values = np.full(self.frame.shape, UNKNOWN, dtype=np.uint8)  # kept in step with _log_odds
        self._disc_radius = -1.0  # the precomputed disc of cell offsets (built on first update)
        self._disc_rc = np.zeros((0, 2), dtype=np.int64)
        self._disc_xy = np.zeros((0, 2))
        self._disc_d = np.zeros(0)
        self._disc_bearing = self._disc_bearing_x = self._disc_bearing_y = np.zeros(0)
        self._owner = np.zeros(0, dtype=np.int64)  # scratch of _independent_runs
        self._disc_x = self._disc_y = np.zeros(0)
        self._disc_r = self._disc_c = np.zeros(0, dtype=np.int64)
        self._disc_span = 0
        self._disc_offsets = np.zeros((3, 0))
        self._numbers = np.zeros(0, dtype=np.int64)  # _sonar_numbers
        self._tables: dict[int, _ConeTable] = {}  # _cone_candidates' tables, by axis bin
        self._all_tables = _AllTables(np.zeros(0, dtype=np.int64), np.zeros(0), 0)  # the same, end to end
        self._sector_cos = np.zeros(0)  # the tables' sector test, per disc cell
        self._tables_key: tuple[float, int] | None = None  # (half cone, disc size) of the tables
        self._ring_of: SonarInfo | None = None  # the sonars _ring describes
        self._ring = _SonarRing((), (), 0.0)
        self.compiled = _use_kernels(kernel)  # update with occupancy_kernels
        # occupancy_kernels.cone_cells' scratch over the cells around the robot (-1 between updates)
        self._marks = np.zeros(0, dtype=np.int32)

    # -- state -------------------------------------------------------------------------------
    def values(self, copy: bool = True) -> np.ndarray:
        """(H, W) uint8 occupancy 0..100 (50 unknown). ``copy=False`` returns the live,
        read-only array (no O(H*W) work; what the planner uses every cycle)."""
        if copy:
            return self._values.copy()
        view = self._values.view()
        view.flags.writeable = False
        return view

    @property
    def log_odds(self) -> np.ndarray:
        """(H, W) float log-odds (read-only view)."""
        view = self._log_odds.view()
        view.flags.writeable = False
        return view

    def reset(self) -> None:
        """Forget everything (all cells unknown)."""
        self._log_odds.fill(0.0)
        self._values.fill(UNKNOWN)

    # -- the sensor update -------------------------------------------------------------------
    def _ensure_disc(self, radius: float) -> None:
        """Precompute cell offsets (dr, dc) within ``radius`` m of a cell centre, sorted by distance."""
        if radius <= self._disc_radius:
            return
        cell = self.frame.cell
        n = math.ceil(radius / cell)
        dr, dc = np.mgrid[-n:n + 1, -n:n + 1]
        d = cell * np.hypot(dr, dc).ravel()
        keep = d <= radius
        order = np.argsort(d[keep], kind="stable")
        self._disc_rc = np.stack([dr.ravel()[keep], dc.ravel()[keep]], axis=1)[order]
        self._disc_xy = self._disc_rc[:, ::-1].astype(float) * cell  # (dx, dy) in m
        self._disc_r = np.ascontiguousarray(self._disc_rc[:, 0])
        self._disc_c = np.ascontiguousarray(self._disc_rc[:, 1])
        self._disc_x = np.ascontiguousarray(self._disc_xy[:, 0])
        self._disc_y = np.ascontiguousarray(self._disc_xy[:, 1])
        self._disc_span = n  # cells from the centre to the disc's edge, along a row or column
        self._disc_d = d[keep][order]
        with np.errstate(invalid="ignore", divide="ignore"):
            bearing = self._disc_xy / self._disc_d[:, None]  # unit (cos, sin) of each offset
        self._disc_bearing = np.nan_to_num(bearing, nan=0.0)  # the centre cell: (0, 0)
        self._disc_bearing_x = np.ascontiguousarray(self._disc_bearing[:, 0])
        self._disc_bearing_y = np.ascontiguousarray(self._disc_bearing[:, 1])
        # (3, n) column, row and flat (row * W + column) offsets as floats (whole numbers, exact)
        self._disc_offsets = np.stack([self._disc_c, self._disc_r,
                                       self._disc_r * self.frame.cols + self._disc_c]).astype(float)
        self._disc_radius = radius
        self._tables_key = None

    def _sector_threshold(self, half_cone: float, slack: float) -> np.ndarray:
        """(n,) per disc cell: the smallest cos(bearing - axis) a cell can have and still lie
        in the (widened) cone of a sonar within ``slack`` m of the disc's centre.

        A cell at distance ``d`` whose bearing from the centre is ``phi`` is seen from the sonar
        at a bearing at most ``asin(slack / d)`` away, and the cone's half-cell widening adds at
        most ``asin(cell / (2 (d - slack)))``: a cheap sector test on precomputed bearings keeps
        the exact cone test to the few cells that can pass it.
        """
        d = self._disc_d
        with np.errstate(divide="ignore", invalid="ignore"):
            shift = np.arcsin(np.minimum(1.0, slack / d))
            widen = np.arcsin(np.minimum(1.0, self.frame.cell / (2 * np.maximum(d - slack, 1e-12))))
        angle = np.nan_to_num(half_cone + shift + widen, nan=math.pi)
        return np.where(angle >= math.pi, -2.0, np.cos(np.minimum(angle, math.pi)) - 1e-9)

    def _cone_candidates(self, tables: list[_ConeTable], reach: list[float]) -> tuple[np.ndarray, list[int]]:
        """The disc cells that can lie in the cones of sonars whose axis directions have these
        ``tables`` (:meth:`_ensure_tables`) and sitting within half a cell's diagonal of the
        disc's centre, among each one's disc cells within ``reach`` (m) of the centre: a superset
        of each cone's cells.

        Returns ``(disc, per_sonar)``: (m,) disc cells, sonar by sonar, each sonar's ascending
        (so by distance); how many are each sonar's.
        """
        parts, counts = [], []
        for table, within in zip(tables, reach, strict=True):
            n = bisect.bisect_right(table.dist, within)
            parts.append(table.cells[:n])
            counts.append(n)
        return np.concatenate(parts), counts

    def _ensure_tables(self, half_cone: float) -> None:
        """Forget the tables if they were made for another cone or disc. There is a table per
        ``_AXIS_BIN`` of axis direction (the sector test widened by half a bin), each built when
        first needed (:meth:`_build_table`; all at once would cost several ms in one cycle)."""
        key = (half_cone, len(self._disc_d))
        if self._tables_key != key:
            self._tables.clear()
            self._all_tables = _AllTables(np.zeros(0, dtype=np.int64), np.zeros(0), 0)
            self._tables_key = key
            self._sector_cos = self._sector_threshold(half_cone + _AXIS_BIN / 2 + 1e-9,
                                                      self.frame.cell * math.sqrt(0.5))

    def _build_table(self, b: int) -> _ConeTable:
        """The table of axis bin ``b``: the disc cells passing the bin's sector test, kept (also
        at the end of :attr:`_all_tables`)."""
        centre = b * _AXIS_BIN
        cells = np.flatnonzero(math.cos(centre) * self._disc_bearing_x
                               + math.sin(centre) * self._disc_bearing_y >= self._sector_cos)
        self._all_tables = self._all_tables.append(cells, self._disc_d[cells])
        table = self._tables[b] = _ConeTable(cells, array.array("d", self._disc_d[cells].tobytes()),
                                             self._all_tables.size - len(cells))
        return table

    def update(self, pose: np.ndarray, ranges: np.ndarray, sonar: SonarInfo) -> None:
        """Fuse one set of sonar readings taken at ``pose``.

        The result is that of fusing the sonars one after the other, in ``sonar`` order (a cell
        in two cones gets the first sonar's update, then the second's on top of it).

        Args:
            pose: (3,) robot pose ``x, y, yaw`` (m, m, rad) in the world frame.
            ranges: (K,) readings in m, in ``sonar`` order; ``>= max_range`` (or not finite)
                means no echo.
            sonar: mount angles/offsets, cone and range limits of the K sonars.
        """
        reading = self._reading(pose, np.asarray(ranges, dtype=float).reshape(-1), sonar)
        if self.compiled:
            self._update_compiled(reading, sonar)
            return
        cells = self._cone_cells(reading, sonar)
        if cells is None:
            return
        flat_lo = self._log_odds.reshape(-1)
        runs = self._independent_runs(cells)
        for run in runs:
            fused = self._fuse(flat_lo, cells, run)
        if len(runs) > 1:  # a cell may have changed in two runs: read its final log-odds
            fused = flat_lo.take(cells.idx)
        # log_odds_to_values, in place
        np.negative(fused, out=fused)
        np.exp(fused, out=fused)
        fused += 1.0
        np.divide(100.0, fused, out=fused)
        self._values.reshape(-1)[cells.idx] = np.rint(fused, out=fused)

    def _reading(self, pose: np.ndarray, ranges: np.ndarray, sonar: SonarInfo) -> _Reading:
        """The per-sonar values of a reading, both paths' input."""
        x, y, yaw = np.asarray(pose, dtype=float)[:3].tolist()
        frame = self.frame
        cell, half_t = frame.cell, self.hit_thickness / 2
        height, width = frame.shape
        if sonar is not self._ring_of:
            self._ring = _SonarRing.of(sonar)
            self._ring_of = sonar
        ring = self._ring
        self._ensure_disc(sonar.max_range + half_t + ring.mount_reach + cell)
        self._ensure_tables(sonar.cone / 2)
        # the robot's cell and its centre: GridFrame.cell_center in scalars
        r0, c0 = frame.cell_of(x, y)
        cx0, cy0 = frame.xmin + (c0 + 0.5) * cell, frame.ymin + (r0 + 0.5) * cell
        cos_y, sin_y = math.cos(yaw), math.sin(yaw)
        # per sonar, with Python's math (the same values the cell tests always used), the row of
        # _SONAR_ROWS (_Reading)
        rows: list[float] = []
        tables: list[_ConeTable] = []
        reach: list[float] = []
        home_span = 0  # the farthest sonar cell from the robot's, along a row or a column
        no_echo_free = math.nextafter(sonar.max_range, math.inf)  # "dist <= max_range"
        for (ox, oy), angle, r in zip(ring.offsets, ring.angles, ranges.tolist(), strict=True):
            sx = x + cos_y * ox - sin_y * oy  # sonar position, world frame
            sy = y + sin_y * ox + cos_y * oy
            a = yaw + angle
            echo = math.isfinite(r) and r < sonar.max_range
            rk, ck = frame.cell_of(sx, sy)
            hr, hc = rk - r0, ck - c0
            home_span = max(home_span, abs(hr), abs(hc))
            # centres within reach of the sonar lie within reach + |sonar - its cell's centre|
            # of its cell's centre
            within = (r + half_t if echo else sonar.max_range) + math.hypot(
                frame.xmin + (ck + 0.5) * cell - sx, frame.ymin + (rk + 0.5) * cell - sy)
            b = round(a / _AXIS_BIN) % _AXIS_BINS
            table = self._tables.get(b)
            if table is None:
                table = self._build_table(b)
            rows += (hc, hr, hr * width + hc, cx0 - sx, cy0 - sy, math.cos(a), math.sin(a),
                     r if echo else -math.inf, r - half_t if echo else no_echo_free,
                     table.start, len(table.cells), within)
            tables.append(table)
            reach.append(within)
        # cells from (r0, c0) to the farthest candidate along a row or a column
        span = self._disc_span + home_span
        return _Reading(np.array(rows).reshape(len(tables), _SONAR_ROWS), tables, reach, r0, c0, span,
                        not (span <= r0 < height - span and span <= c0 < width - span))

    def _cone_cells(self, reading: _Reading, sonar: SonarInfo) -> _ConeCells | None:
        """The cells every sonar of this reading updates, all sonars at once (None: no cell).

        Per sonar ``k`` (in order) its cells come in the disc's order (by distance); a cell in two
        cones appears once per cone. Candidates come from the table of the sonar's axis
        direction (:meth:`_cone_candidates`) around the sonar's own cell (whose centre is within
        half a diagonal of the sonar), cut to its reach; the exact cone and range tests on cell
        centres then decide (module docstring), with the same floating-point operations on the
        same offsets from the robot's cell as always.
        """
        cell, half_t = self.frame.cell, self.hit_thickness / 2
        height, width = self.frame.shape
        half_cone = sonar.cone / 2
        tan_half = math.tan(half_cone)
        r0, c0, span = reading.r0, reading.c0, reading.span
        count = len(reading.rows)
        disc, per_row = self._cone_candidates(reading.tables, reading.reach)
        sonar_of = self._sonar_numbers(count).repeat(per_row)
        # each candidate's sonar row, up to its echo: (_ECHO_ROWS, m)
        per_sonar = reading.rows[:, :_ECHO_ROWS].T.take(sonar_of, axis=1)
        # column, row and flat offsets from the robot's cell (whole numbers, exact as floats)
        offsets = self._disc_offsets.take(disc, axis=1)
        offsets += per_sonar[:3]
        # (dx, dy) from the sonar, m: the same (col, row) -> (dx, dy) arithmetic as the disc's
        dxy = offsets[:2] * cell
        dxy += per_sonar[3:5]
        dx_u, dx_v = dxy * per_sonar[5], dxy * per_sonar[6]  # (dx, dy) times ux and times uy
        along = dx_u[0] + dx_v[1]  # dx ux + dy uy
        lateral = np.subtract(dx_u[1], dx_v[0], out=dx_u[1])  # |dy ux - dx uy|
        np.abs(lateral, out=lateral)
        dist = np.hypot(dxy[0], dxy[1])
        bound = np.multiply(along, tan_half, out=dx_v[0])
        bound += cell / 2
        touched = lateral <= bound
        touched &= along > 0
        np.subtract(dist, per_sonar[7], out=bound)
        occ = np.abs(bound, out=bound) <= half_t
        occ &= touched
        touched &= occ | (dist < per_sonar[8])
        if reading.edges:
            dc, dr = offsets[0], offsets[1]
            touched &= (dr >= -r0) & (dr < height - r0) & (dc >= -c0) & (dc < width - c0)
        keep = touched.nonzero()[0]  # np.flatnonzero without its Python wrappers
        if len(keep) == 0:
            return None
        # >= 0: the cell's row is r0 - span or above
        local = offsets[2].take(keep).astype(np.int64)
        local += span * width + c0
        weight = None
        if self.model == "elfes":
            # angle from the axis on the half-cell-widened cone (module docstring)
            off_axis = lateral.take(keep)
            off_axis -= cell / 2
            weight = np.arctan2(np.maximum(off_axis, 0.0, out=off_axis), along.take(keep))
            weight /= half_cone
            np.square(weight, out=weight)
            np.subtract(1.0, weight, out=weight)
            np.maximum(weight, 0.0, out=weight)
        return _ConeCells(idx=local + (r0 - span) * width, sonar=sonar_of.take(keep), local=local,
                          local_size=(2 * span + 1) * width, occ=occ.take(keep), weight=weight,
                          count=count)

    def _update_compiled(self, reading: _Reading, sonar: SonarInfo) -> None:
        """:meth:`update`'s cells, fusion and values with :mod:`~nav_bench.mapping.occupancy_kernels`
        (the NumPy path's operations: the same log-odds and values, bit for bit); the ``arctan2``
        and ``exp`` stay in NumPy."""
        kernels = _kernels()
        flat_lo = self._log_odds.reshape(-1)
        n, idx, sonar_of, occ, off_axis, along, bounds, runs = self._compiled_cells(reading, sonar)
        if n == 0:
            return
        idx = idx[:n]
        elfes = self.model == "elfes"
        weight = off_axis[:n]
        if elfes:  # angle from the axis on the half-cell-widened cone (module docstring)
            np.arctan2(weight, along[:n], out=weight)
            kernels.elfes_weight(weight, sonar.cone / 2)
        negated = np.empty(n)  # -log-odds of the cells after their run
        for start, stop in itertools.pairwise(bounds[:runs + 1].tolist()):
            arc_exp = kernels.arc_log_odds(flat_lo, idx, occ, start, stop) if elfes else off_axis[:0]
            kernels.fuse(flat_lo, idx, sonar_of, occ, weight, np.exp(arc_exp, out=arc_exp),
                         len(reading.rows), start, stop, elfes, self.l_occ, self.l_free, self.l_min,
                         self.l_max, self.echo_share, negated)
        if runs > 1:  # a cell may have changed in two runs: read its final log-odds
            kernels.negated_log_odds(flat_lo, idx, negated)
        kernels.write_values(self._values.reshape(-1), idx, np.exp(negated, out=negated))

    def _compiled_cells(self, reading: _Reading, sonar: SonarInfo) -> tuple:
        """:func:`~nav_bench.mapping.occupancy_kernels.cone_cells` of a reading (its docstring
        says what it returns)."""
        frame = self.frame
        if len(self._marks) < (2 * reading.span + 1) ** 2:
            self._marks = np.full((2 * reading.span + 3) ** 2, -1, dtype=np.int32)  # a cell to spare
        tables = self._all_tables
        return _kernels().cone_cells(
            tables.cells, tables.dist, reading.rows, self._disc_offsets[0],
            self._disc_offsets[1], frame.cell, math.tan(sonar.cone / 2), self.hit_thickness / 2,
            reading.r0, reading.c0, frame.rows, frame.cols, reading.edges, reading.span, self._marks)

    def _sonar_numbers(self, count: int) -> np.ndarray:
        """(count,) 0, 1, .. count - 1, kept between updates."""
        if len(self._numbers) != count:
            self._numbers = np.arange(count)
        return self._numbers

    def _independent_runs(self, cells: _ConeCells) -> list[slice]:
        """Consecutive runs of sonars whose cones share no cell, as slices of ``cells``' entries.

        Fusing a run at once equals fusing its sonars one after the other; a sonar that shares a
        cell with an earlier one starts a new run, so the earlier update is in place before its
        own (its echo's share depends on the cells' current occupancy)."""
        disc, sonar_of = cells.local, cells.sonar
        if len(self._owner) < cells.local_size:
            self._owner = np.zeros(cells.local_size, dtype=np.int64)
        owner = self._owner
        owner[disc] = sonar_of
        if not np.count_nonzero(owner.take(disc) != sonar_of):  # every cell in one cone only: one run
            return [slice(0, len(disc))]
        order = np.argsort(disc, kind="stable")  # entries of one cell: adjacent, in sonar order
        shared = disc[order[1:]] == disc[order[:-1]]
        later = np.unique(sonar_of[order[1:]][shared])  # sonars sharing a cell with an earlier one
        bounds = [0, *np.searchsorted(sonar_of, later).tolist(), len(disc)]
        return [slice(a, b) for a, b in itertools.pairwise(bounds)]

    def _fuse(self, flat_lo: np.ndarray, cells: _ConeCells, run: slice) -> np.ndarray:
        """Add the inverse sensor model's log-odds to the cells of one run of sonars (no cell
        twice), clamped to ``[l_min, l_max]``; returns the run's new log-odds."""
        idx, occ = cells.idx[run], cells.occ[run]
        lo = flat_lo.take(idx)
        if cells.weight is None:  # "band"
            delta = np.where(occ, self.l_occ, self.l_free)
        else:
            w = cells.weight[run]
            delta = w * self.l_free
            arc = occ.nonzero()[0]
            if len(arc):
                # Konolige's share of each sonar's echo over its own arc: w_i p_i / sum_j w_j p_j
                blame = np.negative(lo.take(arc))
                np.exp(blame, out=blame)
                blame += 1.0
                np.divide(w.take(arc), blame, out=blame)
                sonar_of = cells.sonar[run].take(arc)
                total = np.bincount(sonar_of, weights=blame, minlength=cells.count).take(sonar_of)
                share = np.multiply(self.echo_share, blame)
                if np.minimum.reduce(total) > 0:
                    share /= total
                else:  # no weight on the arc: no evidence
                    share = np.divide(share, total, out=np.zeros(len(arc)), where=total > 0)
                np.minimum(share, 1.0, out=share)
                share *= self.l_occ
                delta[arc] = share
        fused = np.add(lo, delta, out=delta)
        np.minimum(np.maximum(fused, self.l_min, out=fused), self.l_max, out=fused)
        flat_lo[idx] = fused
        return fused


class _ConeTable(NamedTuple):
    """One axis bin's candidate cells (:meth:`OccupancyGrid._cone_candidates`): their disc
    indices (m,), ascending (so by distance from the disc's centre), and those distances, m
    (a flat array of doubles for ``bisect``: no Python float objects for the collector to visit);
    where they start in the grid's :class:`_AllTables`."""

    cells: np.ndarray
    dist: array.array
    start: int


class _AllTables(NamedTuple):
    """The built :class:`_ConeTable` s end to end, for the kernels: ``cells[:size]``,
    ``dist[:size]`` (the arrays have room to grow)."""

    cells: np.ndarray
    dist: np.ndarray
    size: int

    def append(self, cells: np.ndarray, dist: np.ndarray) -> _AllTables:
        """These with one more table at the end (the arrays doubled when full)."""
        size = self.size + len(cells)
        if size > len(self.cells):
            room = max(size, 2 * len(self.cells))
            grown = _AllTables(np.zeros(room, dtype=np.int64), np.zeros(room), self.size)
            grown.cells[:self.size], grown.dist[:self.size] = self.cells[:self.size], self.dist[:self.size]
            return grown.append(cells, dist)
        self.cells[self.size:size], self.dist[self.size:size] = cells, dist
        return _AllTables(self.cells, self.dist, size)


_SONAR_ROWS = 12  # per-sonar values of OccupancyGrid._reading (_Reading.rows)
_ECHO_ROWS = 9  # the first ones, which the cell tests read


class _Reading(NamedTuple):
    """One reading's input to the cell tests (:meth:`OccupancyGrid._reading`).

    Attributes:
        rows: (K, _SONAR_ROWS) per sonar: its cell's column, row and flat offsets from the
            robot's cell, the robot cell's centre less the sonar's position (m), its axis
            (cos, sin), its echo range (m; -inf: no echo), the range below which a cone cell
            is seen through (m); its table's start and length in the grid's
            :class:`_AllTables` and its reach (m, as in ``reach``).
        tables: per sonar the :class:`_ConeTable` of its axis direction.
        reach: per sonar the disc radius around its cell holding its cells, m.
        r0, c0: the robot's cell.
        span: cells from (r0, c0) to the farthest candidate along a row or a column.
        edges: whether candidates may fall outside the grid (the bounds test is needed).
    """

    rows: np.ndarray
    tables: list[_ConeTable]
    reach: list[float]
    r0: int
    c0: int
    span: int
    edges: bool


class _ConeCells(NamedTuple):
    """The cells one reading updates, one entry per (sonar, cell) pair, grouped by sonar.

    Attributes:
        idx: (N,) flat grid index of each entry's cell.
        sonar: (N,) its sonar (non-decreasing).
        local: (N,) its cell's flat index from the first row the reading can reach, in
            ``[0, local_size)``.
        occ: (N,) True on the echo arc, False where seen through.
        weight: (N,) Elfes' angular weight ``w`` ("elfes"), None ("band").
        count: K, the sonars of the reading.
    """

    idx: np.ndarray
    sonar: np.ndarray
    local: np.ndarray
    local_size: int
    occ: np.ndarray
    weight: np.ndarray | None
    count: int


@dataclass(frozen=True)
class _SonarRing:
    """A :class:`SonarInfo`'s mounts as Python floats (the per-sonar arithmetic of an update is
    scalar) and the farthest mount from the robot's centre (m)."""

    offsets: tuple[tuple[float, float], ...]
    angles: tuple[float, ...]
    mount_reach: float

    @classmethod
    def of(cls, sonar: SonarInfo) -> _SonarRing:
        offsets = tuple((float(ox), float(oy)) for ox, oy in np.asarray(sonar.offsets, dtype=float))
        reach = max((math.hypot(ox, oy) for ox, oy in offsets), default=0.0)
        return cls(offsets, tuple(float(a) for a in sonar.angles), reach)


def _kernels() -> ModuleType | None:
    """:mod:`nav_bench.mapping.occupancy_kernels`, or None without Numba (looked up, not kept:
    a grid pickles)."""
    return compiled.load("nav_bench.mapping.occupancy_kernels")


def _use_kernels(kernel: str) -> bool:
    """Whether a grid built with ``kernel`` (:func:`nav_bench.compiled.kernel_choices`) updates
    with the compiled kernels; loads their machine code once per process
    (:func:`_load_compiled_code`)."""
    if not compiled.use_kernels(kernel, _kernels, "occupancy grid"):
        return False
    _load_compiled_code()
    return True


@functools.cache
def _load_compiled_code() -> None:
    """One update per model with the kernels on a small grid (every kernel called, two runs
    and the grid's edge included), so that Numba loads their machine code from its cache (or
    compiles it) while the planner is set up, once per process, not in its first control cycle."""
    sonar = SonarInfo(angles=np.array([0.0, 0.0]), offsets=np.zeros((2, 2)), cone=0.5,
                      min_range=0.05, max_range=1.0)
    for model in SONAR_MODELS:
        grid = OccupancyGrid((0.0, 0.0, 1.0, 1.0), 0.1, model=model, kernel="numpy")
        grid.compiled = True
        grid.update(np.array([0.5, 0.5, 0.0]), np.array([0.3, 0.3]), sonar)
