"""PMT: control cycles per cell (nav_bench.mapping.visits)."""

from __future__ import annotations

import numpy as np
import pytest

from nav_bench.mapping import VisitGrid


def test_counts_cycles_per_cell_and_ignores_points_outside() -> None:
    grid = VisitGrid((0.0, 0.0, 10.0, 10.0))
    assert grid.shape == (100, 100) and grid.counts.sum() == 0
    for xy in [(1.01, 2.01), (1.09, 2.09), (1.05, 2.05), (1.15, 2.05)]:
        assert grid.add(np.array(xy))
    assert grid.counts[20, 10] == 3  # the first three share cell (row 20, col 10)
    assert grid.counts[20, 11] == 1
    assert not grid.add((10.0, 5.0)) and not grid.add((-0.01, 5.0))  # outside: ignored
    assert grid.counts.sum() == 4
    assert grid.cell_center(20, 10) == pytest.approx([1.05, 2.05])
    assert np.issubdtype(grid.counts.dtype, np.integer)


def test_pose_arrays_count_by_position_only_and_reset_clears() -> None:
    grid = VisitGrid((-1.0, -1.0, 1.0, 1.0), cell=0.5)
    assert grid.shape == (4, 4)
    grid.add(np.array([0.1, -0.9, 2.5]))  # a pose (x, y, yaw): yaw ignored
    assert grid.counts[0, 2] == 1
    grid.reset()
    assert grid.counts.sum() == 0
