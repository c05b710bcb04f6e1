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


def test_add_counts_the_cell_grid_frame_names_even_on_cell_edges() -> None:
    # add() works in scalars; GridFrame.world_to_cell / contains (NumPy) must name the same cell
    grid = VisitGrid((-1.0, -2.0, 3.0, 1.0), cell=0.1)
    rng = np.random.default_rng(3)
    edges = np.round(rng.uniform(-1.5, 3.5, (300, 2)), 1)  # on cell edges (in decimal)
    points = np.vstack([edges, rng.uniform(-1.5, 3.5, (300, 2)), [[np.nan, 0.0], [np.inf, 0.0],
                                                                   [0.0, -np.inf], [1e300, 0.0]]])
    expected = np.zeros_like(grid.counts)
    for xy in points:
        with np.errstate(invalid="ignore"):
            row, col = grid.frame.world_to_cell(xy)
        inside = bool(grid.frame.contains(row, col)) and bool(np.isfinite(xy).all())
        if inside:
            expected[row, col] += 1
        assert grid.add(xy) == inside
    np.testing.assert_array_equal(grid.counts, expected)
    assert expected.sum() == 233  # of the 604 points, the ones inside the grid
