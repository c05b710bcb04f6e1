"""The geometry shared by the planner's grids: a fixed rectangle of square cells.

Row 0 is the *bottom* row (y = ymin), column 0 the left column (x = xmin); cell
``(r, c)`` covers ``[xmin + c*cell, xmin + (c+1)*cell) x [ymin + r*cell, ymin + (r+1)*cell)``.
The grid never grows: the paper sizes its map once from the area of the mission
(Sec. 3.2 A), so memory is fixed for an episode. Points outside the grid have cell
indices outside ``[0, H) x [0, W)``; :meth:`GridFrame.contains` tells them apart and
every update ignores them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nav_bench.errors import InputError

Bounds = tuple[float, float, float, float]  # xmin, ymin, xmax, ymax in m

# A planner keeps a few arrays per cell (PMO log-odds and values, PMT counts, D* Lite's g and
# rhs...): at most ~64 bytes, so this many cells stay within about 2 GiB.
MAX_GRID_CELLS = 1 << 25


@dataclass(frozen=True)
class GridFrame:
    """Where a grid lies: lower-left corner, cell side, and size in cells.

    Attributes:
        xmin, ymin: outer corner of cell (0, 0), m.
        cell: cell side, m.
        rows, cols: H and W, cells.
    """

    xmin: float
    ymin: float
    cell: float
    rows: int
    cols: int

    @classmethod
    def from_bounds(cls, bounds: Bounds, cell: float) -> GridFrame:
        """The smallest grid of ``cell``-sized cells covering ``bounds`` (xmin, ymin, xmax, ymax)."""
        xmin, ymin, xmax, ymax = (float(b) for b in bounds)
        if not cell > 0:
            raise InputError(f"grid cell size must be > 0 m, got {cell!r}")
        if not (xmax > xmin and ymax > ymin):
            raise InputError(f"grid bounds must have xmax > xmin and ymax > ymin, got {bounds!r}")
        # 1e-9: 10.0 / 0.1 is 100.00000000000001 in floating point and must stay 100 cells
        cols = max(1, math.ceil((xmax - xmin) / cell - 1e-9))
        rows = max(1, math.ceil((ymax - ymin) / cell - 1e-9))
        if rows * cols > MAX_GRID_CELLS:
            raise InputError(f"a {cols:,} x {rows:,} grid of {cell:g} m cells is over the "
                             f"{MAX_GRID_CELLS:,} cells a planner's map may have; choose a "
                             f"larger cell or a smaller world")
        return cls(xmin, ymin, float(cell), rows, cols)

    @property
    def shape(self) -> tuple[int, int]:
        """(H, W) in cells."""
        return (self.rows, self.cols)

    @property
    def bounds(self) -> Bounds:
        """(xmin, ymin, xmax, ymax) in m of the area the cells cover (may exceed the requested bounds)."""
        return (self.xmin, self.ymin, self.xmin + self.cols * self.cell,
                self.ymin + self.rows * self.cell)

    def world_to_cell(self, xy: np.ndarray | tuple[float, float]) -> np.ndarray:
        """(row, col) int indices of points: (2,) for one point, (..., 2) for (..., 2) points.

        Points outside the grid give indices outside ``[0, H) x [0, W)`` (see :meth:`contains`).
        """
        p = np.asarray(xy, dtype=float)
        col = np.floor((p[..., 0] - self.xmin) / self.cell).astype(np.int64)
        row = np.floor((p[..., 1] - self.ymin) / self.cell).astype(np.int64)
        return np.stack([row, col], axis=-1)

    def cell_of(self, x: float, y: float) -> tuple[int, int]:
        """(row, col) of one finite point (m): :meth:`world_to_cell`'s arithmetic in Python
        floats, the same cell, without NumPy's cost per call (the per-cycle map updates)."""
        return math.floor((y - self.ymin) / self.cell), math.floor((x - self.xmin) / self.cell)

    def cell_center(self, row: np.ndarray | int, col: np.ndarray | int) -> np.ndarray:
        """(x, y) in m of cell centres: (2,) for one cell, (..., 2) for index arrays."""
        x = self.xmin + (np.asarray(col, dtype=float) + 0.5) * self.cell
        y = self.ymin + (np.asarray(row, dtype=float) + 0.5) * self.cell
        return np.stack([x, y], axis=-1)

    def contains(self, row: np.ndarray | int, col: np.ndarray | int) -> np.ndarray:
        """True where ``(row, col)`` is a cell of the grid (bool, broadcast shape of the inputs)."""
        row, col = np.asarray(row), np.asarray(col)
        return (row >= 0) & (row < self.rows) & (col >= 0) & (col < self.cols)


class OnGridFrame:
    """Mixin for a grid that lives on ``self.frame``: its geometry, delegated to the frame."""

    frame: GridFrame

    @property
    def shape(self) -> tuple[int, int]:
        """(H, W) in cells."""
        return self.frame.shape

    @property
    def cell(self) -> float:
        return self.frame.cell

    @property
    def bounds(self) -> Bounds:
        """(xmin, ymin, xmax, ymax) in m actually covered by the cells."""
        return self.frame.bounds

    def world_to_cell(self, xy: np.ndarray | tuple[float, float]) -> np.ndarray:
        """(row, col) of points, see :meth:`GridFrame.world_to_cell`."""
        return self.frame.world_to_cell(xy)

    def cell_center(self, row: np.ndarray | int, col: np.ndarray | int) -> np.ndarray:
        """(x, y) of cell centres, see :meth:`GridFrame.cell_center`."""
        return self.frame.cell_center(row, col)
