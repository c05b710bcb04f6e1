"""Map quality (nav_bench.mapping.quality) on hand-built grids with exact expected numbers."""

from __future__ import annotations

import numpy as np
import pytest

from nav_bench.interface import GridState
from nav_bench.mapping.quality import (
    MAP_QUALITY_FIELDS,
    map_quality,
    path_cells,
    true_occupancy,
    within_one_cell,
)
from nav_bench.world.geometry import StaticGeometry

BOUNDS = (0.0, 0.0, 1.0, 1.0)  # 10 x 10 cells of 0.1 m


def hand_built() -> tuple[GridState, np.ndarray]:
    """A true wall in column 5 (x 0.5..0.6); the planner observed columns 2..7 (free, 20) and
    marks occupied (100): column 5 rows 0..5 (right), column 4 rows 0..1 (one cell off the
    wall: right within the tolerance), column 2 row 8 (three cells off: a phantom)."""
    truth = np.zeros((10, 10), dtype=bool)
    truth[:, 5] = True
    pmo = np.full((10, 10), 50, dtype=np.uint8)
    pmo[:, 2:8] = 20
    pmo[0:6, 5] = 100
    pmo[0:2, 4] = 100
    pmo[8, 2] = 100
    return GridState(pmo=pmo, bounds=BOUNDS, cell=0.1), truth


def test_precision_recall_and_phantom_share_on_a_hand_built_grid() -> None:
    grids, truth = hand_built()
    # the route along row 8 (y = 0.85) from x = 0.05 to 0.95: it crosses the wall's cell
    # (true occupied, not counted) and the phantom at column 2
    q = map_quality(grids, truth, np.array([[0.05, 0.85], [0.95, 0.85]]))
    assert q.occupied_cells == 9
    assert q.precision == pytest.approx(8 / 9)  # all but the phantom lie within a cell of the wall
    # the wall's 10 observed cells: rows 0..6 have a marked cell within one cell (row 6 is
    # next to row 5), rows 7..9 do not
    assert q.recall == pytest.approx(7 / 10)
    assert (q.path_cells, q.phantom_cells) == (9, 1)
    assert q.phantom_share == pytest.approx(1 / 9)
    assert q.observed_cells == 60


def test_without_a_one_cell_tolerance_the_neighbour_cells_would_count_as_wrong() -> None:
    # the two cells of column 4 sit where a sonar echo off the wall's face lands: the measure
    # counts them right, a cell two columns away wrong
    grids, truth = hand_built()
    pmo = grids.pmo.copy()
    pmo[0:2, 4] = 20
    pmo[0:2, 3] = 100  # two cells off the wall
    q = map_quality(GridState(pmo=pmo, bounds=BOUNDS, cell=0.1), truth, None)
    assert q.precision == pytest.approx(6 / 9)


def test_undefined_shares_are_null_and_the_row_fields_are_named() -> None:
    truth = np.zeros((10, 10), dtype=bool)
    grids = GridState(pmo=np.full((10, 10), 50, dtype=np.uint8), bounds=BOUNDS, cell=0.1)
    q = map_quality(grids, truth, None)  # nothing observed, goal unreachable
    assert (q.precision, q.recall, q.phantom_share) == (None, None, None)
    assert (q.observed_cells, q.occupied_cells, q.path_cells, q.phantom_cells) == (0, 0, 0, 0)
    assert tuple(q.row_fields()) == MAP_QUALITY_FIELDS


def test_within_one_cell_and_path_cells() -> None:
    mask = np.zeros((5, 5), dtype=bool)
    mask[2, 2] = True
    assert within_one_cell(mask).sum() == 9 and within_one_cell(mask)[1:4, 1:4].all()
    grids = GridState(pmo=np.zeros((10, 10), dtype=np.uint8), bounds=BOUNDS, cell=0.1)
    # a diagonal through cell corners: each sample falls in one cell; off-grid points dropped
    cells = path_cells(np.array([[0.05, 0.05], [0.35, 0.05], [0.35, 0.25], [1.5, 0.25]]), grids)
    assert cells.tolist() == [[0, 0], [0, 1], [0, 2], [0, 3], [1, 3], [2, 3], [2, 4], [2, 5],
                              [2, 6], [2, 7], [2, 8], [2, 9]]


def test_true_occupancy_rasterises_thin_walls_on_the_planner_cells() -> None:
    # a 4 cm wall along x = 0.56 (thinner than a cell) still owns its column; cells outside the
    # world rectangle [0, 1] x [0, 1] (the grid's margin) count as occupied
    boxes = np.array([[0.56, 0.5, 0.04, 1.0, 0.0]])  # cx, cy, sx, sy, yaw
    geometry = StaticGeometry(size=(1.0, 1.0), boxes=boxes, cylinders=np.zeros((0, 3)),
                              box_source=np.zeros(1, dtype=int), cylinder_source=np.zeros(0, dtype=int),
                              height=0.5)
    grids = GridState(pmo=np.zeros((12, 12), dtype=np.uint8), bounds=(-0.1, -0.1, 1.1, 1.1), cell=0.1)
    truth = true_occupancy(geometry, grids)
    assert truth[1:11, 6].all() and truth[1:11, 1:6].sum() == 0 and truth[1:11, 7:11].sum() == 0
    assert truth[0].all() and truth[11].all() and truth[:, 0].all() and truth[:, 11].all()
