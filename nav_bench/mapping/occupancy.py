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

Speed: one update touches only the cells of a disc around the robot, precomputed once as
cell offsets sorted by distance; each sonar takes the prefix within its reach and works on
the cells of its cone only. There is no Python loop over cells, only over the sonars
(``benchmarks/bench_sonar_map.py``).
"""

from __future__ import annotations

import math

import numpy as np

from nav_bench.errors import InputError
from nav_bench.interface import SonarInfo
from nav_bench.mapping.grid import Bounds, GridFrame, OnGridFrame

UNKNOWN = 50  # value of a cell never observed (log-odds 0)
SONAR_MODELS = ("elfes", "band")  # inverse sensor models, see the module docstring


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

    Points and cells outside the grid are ignored by :meth:`update`.
    """

    def __init__(self, bounds: Bounds, cell: float = 0.1, *, model: str = "elfes",
                 l_occ: float = 0.85, l_free: float = -0.4, l_min: float = -2.0,
                 l_max: float = 3.5, hit_thickness: float | None = None,
                 echo_share: float = 2.0) -> None:
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
        self._disc_bearing = np.zeros((0, 2))
        self._disc_x = self._disc_y = np.zeros(0)
        self._disc_span = 0
        self._disc_flat = np.zeros(0, dtype=np.int64)
        self._sector_key: tuple[float, float, int] | None = None
        self._sector_cos = np.zeros(0)

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
        self._disc_x = np.ascontiguousarray(self._disc_xy[:, 0])
        self._disc_y = np.ascontiguousarray(self._disc_xy[:, 1])
        self._disc_span = n  # cells from the centre to the disc's edge, along a row or column
        self._disc_flat = self._disc_rc[:, 0] * self.frame.cols + self._disc_rc[:, 1]  # flat offsets
        self._disc_d = d[keep][order]
        with np.errstate(invalid="ignore", divide="ignore"):
            bearing = self._disc_xy / self._disc_d[:, None]  # unit (cos, sin) of each offset
        self._disc_bearing = np.nan_to_num(bearing, nan=0.0)  # the centre cell: (0, 0)
        self._disc_radius = radius
        self._sector_key = None

    def _sector_threshold(self, half_cone: float, slack: float) -> np.ndarray:
        """(n,) per disc cell: the smallest cos(bearing - axis) a cell can have and still lie
        in the (widened) cone of a sonar within ``slack`` m of the disc's centre.

        A cell at distance ``d`` whose bearing from the centre is ``phi`` is seen from the sonar
        at a bearing at most ``asin(slack / d)`` away, and the cone's half-cell widening adds at
        most ``asin(cell / (2 (d - slack)))``: a cheap sector test on precomputed bearings keeps
        the exact cone test to the few cells that can pass it.
        """
        key = (half_cone, slack, len(self._disc_d))
        if self._sector_key != key:
            d = self._disc_d
            with np.errstate(divide="ignore", invalid="ignore"):
                shift = np.arcsin(np.minimum(1.0, slack / d))
                widen = np.arcsin(np.minimum(1.0, self.frame.cell / (2 * np.maximum(d - slack, 1e-12))))
            angle = np.nan_to_num(half_cone + shift + widen, nan=math.pi)
            self._sector_cos = np.where(angle >= math.pi, -2.0, np.cos(np.minimum(angle, math.pi)) - 1e-9)
            self._sector_key = key
        return self._sector_cos

    def update(self, pose: np.ndarray, ranges: np.ndarray, sonar: SonarInfo) -> None:
        """Fuse one set of sonar readings taken at ``pose``.

        Args:
            pose: (3,) robot pose ``x, y, yaw`` (m, m, rad) in the world frame.
            ranges: (K,) readings in m, in ``sonar`` order; ``>= max_range`` (or not finite)
                means no echo.
            sonar: mount angles/offsets, cone and range limits of the K sonars.
        """
        x, y, yaw = (float(v) for v in pose[:3])
        ranges = np.asarray(ranges, dtype=float).reshape(-1)
        cell, half_t = self.frame.cell, self.hit_thickness / 2
        mount_reach = float(np.max(np.hypot(sonar.offsets[:, 0], sonar.offsets[:, 1]), initial=0.0))
        self._ensure_disc(sonar.max_range + half_t + mount_reach + cell)
        r0, c0 = (int(v) for v in self.frame.world_to_cell((x, y)))
        cx0, cy0 = (float(v) for v in self.frame.cell_center(r0, c0))
        half_cone = sonar.cone / 2
        tan_half = math.tan(half_cone)
        # a sonar lies within mount_reach of the robot, the robot within half a diagonal of cell0's centre
        sector = self._sector_threshold(half_cone, mount_reach + cell * math.sqrt(0.5))
        cos_y, sin_y = math.cos(yaw), math.sin(yaw)
        height, width = self.frame.shape
        span = self._disc_span  # the whole disc on the grid: no cell needs a bounds check
        inside = span <= r0 < height - span and span <= c0 < width - span
        flat_lo = self._log_odds.reshape(-1)
        elfes = self.model == "elfes"
        updated = []
        for k in range(len(ranges)):
            ox, oy = sonar.offsets[k]
            sx = x + cos_y * ox - sin_y * oy  # sonar position, world frame
            sy = y + sin_y * ox + cos_y * oy
            a = yaw + sonar.angles[k]
            ux, uy = math.cos(a), math.sin(a)
            r = float(ranges[k])
            echo = math.isfinite(r) and r < sonar.max_range
            reach = r + half_t if echo else sonar.max_range
            # centres within `reach` of the sonar lie within reach + |sonar - cell0| of cell0's centre
            n = int(np.searchsorted(self._disc_d, reach + math.hypot(sx - cx0, sy - cy0), "right"))
            near = np.flatnonzero(self._disc_bearing[:n] @ np.array([ux, uy]) >= sector[:n])
            dx = self._disc_x[near] + (cx0 - sx)
            dy = self._disc_y[near] + (cy0 - sy)
            along = dx * ux + dy * uy
            lateral = np.abs(dy * ux - dx * uy)
            cone = (along > 0) & (lateral <= along * tan_half + cell / 2)
            dist = np.hypot(dx, dy)
            if echo:
                occ = cone & (np.abs(dist - r) <= half_t)
                touched = occ | (cone & (dist < r - half_t))
            else:
                occ = None
                touched = cone & (dist <= sonar.max_range)
            if inside:
                idx = (r0 * width + c0) + self._disc_flat[near[touched]]  # unique within one sonar
            else:
                rows = r0 + self._disc_rc[near, 0]
                cols = c0 + self._disc_rc[near, 1]
                touched &= (rows >= 0) & (rows < height) & (cols >= 0) & (cols < width)
                idx = rows[touched] * width + cols[touched]
            lo = flat_lo[idx]
            occ = occ[touched] if occ is not None else None
            if elfes:
                # angle from the axis on the half-cell-widened cone (module docstring)
                theta = np.arctan2(np.maximum(lateral[touched] - cell / 2, 0.0), along[touched])
                w = np.maximum(1.0 - np.square(theta / half_cone), 0.0)
                delta = w * self.l_free
                if occ is not None and occ.any():
                    blame = w[occ] / (1.0 + np.exp(-lo[occ]))  # w_i * p_i
                    total = float(blame.sum())
                    delta[occ] = (self.l_occ * np.minimum(1.0, self.echo_share * blame / total)
                                  if total > 0 else 0.0)
            elif occ is not None:
                delta = np.where(occ, self.l_occ, self.l_free)
            else:
                delta = self.l_free
            flat_lo[idx] = np.minimum(np.maximum(lo + delta, self.l_min), self.l_max)
            updated.append(idx)
        if updated:
            idx = np.concatenate(updated)
            self._values.reshape(-1)[idx] = log_odds_to_values(flat_lo[idx])
