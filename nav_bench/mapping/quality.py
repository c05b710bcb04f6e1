"""Map quality: how well a planner's occupancy grid matches the true world, at the episode's end.

A benchmark that compares navigation outcomes should say whether a planner failed for its
method or because its map drew a wall that is not there. :func:`map_quality` compares a
planner's grid (0..100, 50 unknown; :class:`~nav_bench.interface.GridState`) with the true
static geometry on the same cells:

* **observed** cells: value != 50 (the sonars said something about them);
* **predicted occupied**: value > :data:`OCCUPIED_ABOVE` (65, the obstacle threshold of EO/PC
  and D* Lite by default; one threshold for every planner so their maps compare);
* **true occupied**: the cells the static geometry covers (boundary walls included), rasterised
  on the planner's own cells with :func:`~nav_bench.world.raster.rasterize` at
  ``inflate = cell / 2`` (a cell whose centre lies within half a cell of an obstacle: walls
  thinner than a cell still own their cells).

Tolerance of one cell: a sonar echo sits on an obstacle's *surface* and the sensor model's arc
is one cell thick, so the cell that holds the echo is often the free neighbour of the
obstacle's own cell. A predicted occupied cell therefore counts as correct when a true occupied
cell lies within one cell of it (its 8 neighbours or itself), and a true occupied cell counts
as found when a predicted occupied cell lies within one cell of it. A phantom wall across a
1 m door (cells 0.1 m to 0.5 m from both jambs) still counts as wrong.

* ``precision``: correct predicted occupied / predicted occupied (null: none predicted);
* ``recall``: observed true occupied cells found / observed true occupied (null: none observed);
* ``phantom share``: of the true free cells the shortest path crosses (the optimal path of
  :func:`~nav_bench.world.optimal.optimal_path`, the same one ``optimal_length_m`` measures,
  sampled every quarter cell), the share the map marks occupied: walls the planner invented
  across its best route (null when the goal is unreachable).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from nav_bench.interface import GridState
from nav_bench.world.geometry import StaticGeometry
from nav_bench.world.raster import rasterize

OCCUPIED_ABOVE = 65  # a cell is an obstacle above this (0..100), as EO/PC and D* Lite read it
UNKNOWN = 50  # the value of a cell never observed
TOLERANCE_CELLS = 1  # an occupied cell within this many cells (Chebyshev) of the truth is right

# the row's fields, in order (nav_bench.episode.row.ResultRow); see MapQuality
MAP_QUALITY_FIELDS = ("map_precision", "map_recall", "map_phantom_share", "map_observed_cells",
                      "map_occupied_cells", "map_path_cells", "map_phantom_cells")


@dataclass(frozen=True)
class MapQuality:
    """A planner's final grid against the truth (module docstring for the definitions).

    Attributes:
        precision: share of predicted occupied cells that are true obstacles (+-1 cell), or None.
        recall: share of observed true obstacle cells the map marks occupied (+-1 cell), or None.
        phantom_share: share of the optimal path's true free cells marked occupied, or None.
        observed_cells: cells with a value other than 50.
        occupied_cells: cells above :data:`OCCUPIED_ABOVE`.
        path_cells: true free cells on the optimal path (0 when unreachable).
        phantom_cells: of those, the cells marked occupied.
    """

    precision: float | None
    recall: float | None
    phantom_share: float | None
    observed_cells: int
    occupied_cells: int
    path_cells: int
    phantom_cells: int

    def row_fields(self) -> dict[str, Any]:
        """The row's ``map_*`` fields (:data:`MAP_QUALITY_FIELDS`)."""
        values = (self.precision, self.recall, self.phantom_share, self.observed_cells,
                  self.occupied_cells, self.path_cells, self.phantom_cells)
        return dict(zip(MAP_QUALITY_FIELDS, values, strict=True))


def grid_cell(grids: GridState) -> float:
    """Cell side (m) of a planner's grid: as stated, else from its bounds and shape."""
    if grids.cell is not None:
        return float(grids.cell)
    xmin, _, xmax, _ = grids.bounds
    return (xmax - xmin) / grids.pmo.shape[1]


def true_occupancy(geometry: StaticGeometry, grids: GridState) -> np.ndarray:
    """(H, W) bool: the planner's cells the static geometry covers (module docstring)."""
    cell = grid_cell(grids)
    height, width = grids.pmo.shape
    xmin, ymin = grids.bounds[0], grids.bounds[1]
    bounds = (xmin, ymin, xmin + width * cell, ymin + height * cell)
    raster = rasterize(geometry, cell, inflate=cell / 2, bounds=bounds)
    return raster.occupied[:height, :width]


def within_one_cell(mask: np.ndarray) -> np.ndarray:
    """(H, W) bool: cells with a True cell of ``mask`` among themselves and their 8 neighbours."""
    out = mask.copy()
    padded = np.pad(mask, TOLERANCE_CELLS)
    height, width = mask.shape
    for dr in range(2 * TOLERANCE_CELLS + 1):
        for dc in range(2 * TOLERANCE_CELLS + 1):
            out |= padded[dr:dr + height, dc:dc + width]
    return out


def path_cells(path: np.ndarray, grids: GridState) -> np.ndarray:
    """(N, 2) distinct (row, col) cells of the planner's grid a polyline (M, 2) m crosses,
    sampled every quarter cell; cells off the grid are dropped."""
    path = np.asarray(path, dtype=float).reshape(-1, 2)
    cell = grid_cell(grids)
    if len(path) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    if len(path) == 1:
        samples = path
    else:
        seg = np.diff(path, axis=0)
        n = np.maximum(1, np.ceil(np.hypot(seg[:, 0], seg[:, 1]) / (cell / 4)).astype(int))
        t = np.concatenate([np.arange(k) / k for k in n])  # per-segment fractions in [0, 1)
        start = np.repeat(path[:-1], n, axis=0)
        samples = np.vstack([start + np.repeat(seg, n, axis=0) * t[:, None], path[-1:]])
    xmin, ymin = grids.bounds[0], grids.bounds[1]
    rc = np.stack([np.floor((samples[:, 1] - ymin) / cell), np.floor((samples[:, 0] - xmin) / cell)],
                  axis=1).astype(np.int64)
    height, width = grids.pmo.shape
    inside = (rc[:, 0] >= 0) & (rc[:, 0] < height) & (rc[:, 1] >= 0) & (rc[:, 1] < width)
    return np.unique(rc[inside], axis=0)


def map_quality(grids: GridState, truth: np.ndarray, optimal_path: np.ndarray | None) -> MapQuality:
    """Compare a planner's grid with the truth on its own cells.

    Args:
        grids: the planner's final grid (``pmo`` (H, W) 0..100, bounds, cell).
        truth: (H, W) bool true occupancy of the same cells (:func:`true_occupancy`).
        optimal_path: (N, 2) m, the shortest path start -> goal; None when unreachable.
    """
    values = np.asarray(grids.pmo)
    if truth.shape != values.shape:
        raise ValueError(f"truth {truth.shape} and grid {values.shape} differ in shape")
    observed = values != UNKNOWN
    predicted = values > OCCUPIED_ABOVE
    n_predicted = int(predicted.sum())
    correct = int((predicted & within_one_cell(truth)).sum())
    seen_true = truth & observed
    n_seen_true = int(seen_true.sum())
    found = int((seen_true & within_one_cell(predicted)).sum())
    if optimal_path is None or len(optimal_path) == 0:
        n_path = n_phantom = 0
        phantom_share = None
    else:
        rc = path_cells(optimal_path, grids)
        free = ~truth[rc[:, 0], rc[:, 1]]
        rc = rc[free]
        n_path = len(rc)
        n_phantom = int(predicted[rc[:, 0], rc[:, 1]].sum())
        phantom_share = n_phantom / n_path if n_path else None
    return MapQuality(precision=correct / n_predicted if n_predicted else None,
                      recall=found / n_seen_true if n_seen_true else None,
                      phantom_share=phantom_share, observed_cells=int(observed.sum()),
                      occupied_cells=n_predicted, path_cells=n_path, phantom_cells=n_phantom)
