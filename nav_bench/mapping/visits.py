"""PMT, the trajectory grid: how many control cycles the robot centre spent in each cell.

The paper's iteration risk (RI) and trajectory intensity (IPT) read it to steer re-plans
away from places the robot has already been (Sec. 2.1). The count grows by one per
control cycle, so a robot turning in place at a breakpoint marks that cell heavily: that
is intended, a spot where the robot lingered is a spot to leave.
"""

from __future__ import annotations

import math

import numpy as np

from nav_bench.mapping.grid import Bounds, GridFrame, OnGridFrame


class VisitGrid(OnGridFrame):
    """Visit counts over a fixed rectangle.

    Args:
        bounds: (xmin, ymin, xmax, ymax) in m; the grid covers at least this rectangle.
        cell: cell side, m.

    Attributes:
        counts: (H, W) int64, control cycles spent with the robot centre in each cell.

    Points outside the grid are ignored (:meth:`add` returns False for them).
    """

    def __init__(self, bounds: Bounds, cell: float = 0.1) -> None:
        self.frame = GridFrame.from_bounds(bounds, cell)
        self.counts = np.zeros(self.frame.shape, dtype=np.int64)

    def add(self, xy: np.ndarray | tuple[float, float]) -> bool:
        """Count one control cycle at point ``xy`` (m). False (nothing counted) outside the grid."""
        x, y = float(xy[0]), float(xy[1])
        if not (math.isfinite(x) and math.isfinite(y)):
            return False
        frame = self.frame
        row, col = frame.cell_of(x, y)
        if not (0 <= row < frame.rows and 0 <= col < frame.cols):
            return False
        self.counts[row, col] += 1
        return True

    def reset(self) -> None:
        """Zero every count."""
        self.counts.fill(0)
