"""Occupancy rasters of the true static geometry (for optimal paths, difficulty, imports).

A :class:`Raster` is a boolean grid over an axis-aligned rectangle. Row 0 is the
*bottom* row (y = ymin), column 0 the left column (x = xmin); cell ``(r, c)`` covers
``[x0 + c*res, x0 + (c+1)*res) x [y0 + r*res, y0 + (r+1)*res)``. A cell is occupied when
its **centre** lies within ``inflate`` metres of an obstacle (or inside one), so
rasterising with ``inflate = robot_radius`` gives the configuration space of a disc robot.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from nav_bench.errors import InputError
from nav_bench.world.geometry import StaticGeometry, signed_distances

Bounds = tuple[float, float, float, float]  # xmin, ymin, xmax, ymax in m

# Memory budget of one raster. The finest raster nav-bench makes of a world is the optimal
# path's (RASTER_CELL_M); its search graph keeps about 230 bytes per cell (measured: 0.99 GB
# for a 100 m x 100 m world), so a world may cover at most ~8.4 M such cells (~21,000 m^2,
# e.g. 140 m x 140 m). Worlds beyond it are refused when they are validated.
RASTER_CELL_M = 0.05
RASTER_BUDGET_BYTES = 2 << 30
RASTER_BYTES_PER_CELL = 256


def raster_budget_problem(shape: tuple[int, int], resolution: float) -> str | None:
    """Why a raster of ``shape`` cells would exceed :data:`RASTER_BUDGET_BYTES` (None: it fits)."""
    cells = shape[0] * shape[1]
    need = cells * RASTER_BYTES_PER_CELL
    if need <= RASTER_BUDGET_BYTES:
        return None
    most = RASTER_BUDGET_BYTES / RASTER_BYTES_PER_CELL * resolution**2
    return (f"needs a {shape[1]:,} x {shape[0]:,} cell raster at {resolution:g} m (about "
            f"{_gib(need)}), over the memory budget of {_gib(RASTER_BUDGET_BYTES)}: a world may "
            f"cover at most about {most:,.0f} m^2")


def _gib(n: float) -> str:
    return f"{n / 2**30:,.1f} GiB" if n < 2**40 else f"{n / 2**40:,.1f} TiB"


@dataclass(frozen=True)
class Raster:
    """A boolean occupancy grid.

    Attributes:
        occupied: (H, W) bool; row 0 at y = ymin (the bottom), column 0 at x = xmin.
        origin: (x0, y0) in m, the outer corner of cell (0, 0).
        resolution: cell side in m.
    """

    occupied: np.ndarray
    origin: tuple[float, float]
    resolution: float

    @property
    def shape(self) -> tuple[int, int]:
        """(H, W) in cells."""
        return self.occupied.shape  # type: ignore[return-value]

    @property
    def bounds(self) -> Bounds:
        """(xmin, ymin, xmax, ymax) in m of the area the grid covers."""
        h, w = self.occupied.shape
        x0, y0 = self.origin
        return (x0, y0, x0 + w * self.resolution, y0 + h * self.resolution)

    def world_to_cell(self, xy: np.ndarray | tuple[float, float]) -> np.ndarray:
        """(row, col) int cells of points; (2,) for one point, (K, 2) for (K, 2) points.

        Points outside the grid give indices outside ``[0, H) x [0, W)``; see :meth:`inside`.
        """
        p = np.asarray(xy, dtype=float)
        col = np.floor((p[..., 0] - self.origin[0]) / self.resolution).astype(int)
        row = np.floor((p[..., 1] - self.origin[1]) / self.resolution).astype(int)
        return np.stack([row, col], axis=-1)

    def cell_center(self, row: np.ndarray | int, col: np.ndarray | int) -> np.ndarray:
        """(x, y) in m of cell centres; shape (..., 2) following ``row``/``col``."""
        r = np.asarray(row, dtype=float)
        c = np.asarray(col, dtype=float)
        return np.stack([self.origin[0] + (c + 0.5) * self.resolution,
                         self.origin[1] + (r + 0.5) * self.resolution], axis=-1)

    def inside(self, rc: np.ndarray) -> np.ndarray:
        """Bool mask: (row, col) pairs ``rc`` (..., 2) that lie on the grid."""
        rc = np.asarray(rc)
        h, w = self.occupied.shape
        return (rc[..., 0] >= 0) & (rc[..., 0] < h) & (rc[..., 1] >= 0) & (rc[..., 1] < w)

    def is_free(self, xy: np.ndarray) -> np.ndarray:
        """Bool per point (..., 2): on the grid and in a free cell."""
        p = np.asarray(xy, dtype=float)
        col = np.floor((p[..., 0] - self.origin[0]) / self.resolution).astype(np.intp)
        row = np.floor((p[..., 1] - self.origin[1]) / self.resolution).astype(np.intp)
        h, w = self.occupied.shape
        ok = (row >= 0) & (row < h) & (col >= 0) & (col < w)
        out = np.zeros(ok.shape, dtype=bool)
        out[ok] = ~self.occupied[row[ok], col[ok]]
        return out

    def distance_field(self) -> np.ndarray:
        """(H, W) float, metres from each cell centre to the nearest occupied cell centre.

        Occupied cells read 0. Exact Euclidean transform (scipy ``distance_transform_edt``);
        a grid with no occupied cell reads ``inf`` everywhere.
        """
        if not self.occupied.any():
            return np.full(self.occupied.shape, np.inf)
        from scipy import ndimage  # here, not on top: validate imports this module (0.7 s)

        return ndimage.distance_transform_edt(~self.occupied) * self.resolution


def grid_shape(bounds: Bounds, resolution: float) -> tuple[int, int]:
    """(H, W) cells covering ``bounds`` (a partial last cell counts as a cell)."""
    xmin, ymin, xmax, ymax = bounds
    # the small tolerance keeps 10.0 / 0.05 at 200 cells despite rounding
    w = max(1, math.ceil((xmax - xmin) / resolution - 1e-9))
    h = max(1, math.ceil((ymax - ymin) / resolution - 1e-9))
    return h, w


def _primitive_aabbs(geometry: StaticGeometry) -> np.ndarray:
    """(N + M, 4) xmin, ymin, xmax, ymax of every box then every cylinder (m)."""
    b = geometry.boxes
    c, s = np.abs(np.cos(b[:, 4])), np.abs(np.sin(b[:, 4]))
    hx = c * b[:, 2] / 2 + s * b[:, 3] / 2
    hy = s * b[:, 2] / 2 + c * b[:, 3] / 2
    boxes = np.stack([b[:, 0] - hx, b[:, 1] - hy, b[:, 0] + hx, b[:, 1] + hy], axis=1)
    cy = geometry.cylinders
    cyls = np.stack([cy[:, 0] - cy[:, 2], cy[:, 1] - cy[:, 2],
                     cy[:, 0] + cy[:, 2], cy[:, 1] + cy[:, 2]], axis=1)
    return np.concatenate([boxes.reshape(-1, 4), cyls.reshape(-1, 4)])


def rasterize(geometry: StaticGeometry, resolution: float, inflate: float = 0.0,
              bounds: Bounds | None = None, chunk_cells: int = 1 << 20) -> Raster:
    """Rasterise static geometry: a cell is occupied if its centre is within ``inflate`` of it.

    Each primitive is evaluated only on the cells of its bounding box grown by ``inflate``
    (so thousands of small obstacles cost no more than their area), with
    :func:`~nav_bench.world.geometry.signed_distances`, the same formula as ``clearance``.

    Args:
        geometry: the world's primitives (boundary walls included when the world has them).
        resolution: cell side in m (> 0).
        inflate: m; occupied when signed distance <= inflate (the disc robot's radius for a
            configuration-space raster; 0 rasterises the obstacles themselves).
        bounds: (xmin, ymin, xmax, ymax) in m; default the world ``[0, sx] x [0, sy]``.
            Cells whose centre lies outside the world rectangle are occupied.
        chunk_cells: at most this many cells are evaluated at once (bounds memory).
    Returns:
        the :class:`Raster`.
    """
    if resolution <= 0:
        raise ValueError(f"resolution must be > 0, got {resolution}")
    sx, sy = geometry.size
    bounds = (0.0, 0.0, sx, sy) if bounds is None else tuple(map(float, bounds))  # type: ignore[assignment]
    h, w = grid_shape(bounds, resolution)
    problem = raster_budget_problem((h, w), resolution)
    if problem is not None:
        raise InputError(f"this world {problem}")
    x0, y0 = bounds[0], bounds[1]
    xs = x0 + (np.arange(w) + 0.5) * resolution  # cell-centre coordinates
    ys = y0 + (np.arange(h) + 0.5) * resolution
    occupied = np.zeros((h, w), dtype=bool)
    # outside the world rectangle counts as occupied
    occupied[:, (xs < 0.0) | (xs > sx)] = True
    occupied[(ys < 0.0) | (ys > sy), :] = True

    n_boxes = len(geometry.boxes)
    aabbs = _primitive_aabbs(geometry)
    empty_boxes = np.zeros((0, 5))
    empty_cyls = np.zeros((0, 3))
    for i, (axmin, aymin, axmax, aymax) in enumerate(aabbs):
        c0 = max(0, math.floor((axmin - inflate - x0) / resolution))
        c1 = min(w, math.ceil((axmax + inflate - x0) / resolution) + 1)
        r0 = max(0, math.floor((aymin - inflate - y0) / resolution))
        r1 = min(h, math.ceil((aymax + inflate - y0) / resolution) + 1)
        if c0 >= c1 or r0 >= r1:
            continue
        if i < n_boxes:
            single = dataclasses.replace(geometry, boxes=geometry.boxes[i:i + 1],
                                         cylinders=empty_cyls)
        else:
            j = i - n_boxes
            single = dataclasses.replace(geometry, boxes=empty_boxes,
                                         cylinders=geometry.cylinders[j:j + 1])
        rows_per_chunk = max(1, chunk_cells // (c1 - c0))
        for ra in range(r0, r1, rows_per_chunk):
            rb = min(r1, ra + rows_per_chunk)
            gx, gy = np.meshgrid(xs[c0:c1], ys[ra:rb])
            db, dc = signed_distances(single, np.column_stack([gx.ravel(), gy.ravel()]))
            d = (db if i < n_boxes else dc)[:, 0].reshape(rb - ra, c1 - c0)
            occupied[ra:rb, c0:c1] |= d <= inflate
    return Raster(occupied=occupied, origin=(x0, y0), resolution=float(resolution))
