"""Shared steps of the grid-map importers: blocked cells -> boxes, automatic start and goal."""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy import ndimage

from nav_bench.errors import InputError
from nav_bench.specs import WorldSpec, default_robot_radius
from nav_bench.world.geometry import static_geometry
from nav_bench.world.imports.rectangles import merge_cells
from nav_bench.world.optimal import free_cell_near, grid_distances, grid_graph
from nav_bench.world.raster import rasterize

EIGHT = np.ones((3, 3), dtype=bool)  # 8-connectivity for ndimage.label


def q(value: float) -> float:
    """A coordinate rounded to 1e-6 m for readable YAML (plain float, not numpy)."""
    return float(round(float(value), 6)) + 0.0  # + 0.0 turns -0.0 into 0.0


def blocked_to_boxes(blocked: np.ndarray, cell: float) -> list[dict[str, Any]]:
    """Obstacle entries (``box``) covering the True cells of a (H, W) grid, row 0 at y = 0.

    Cells are merged into few rectangles by :func:`merge_cells`; cell (r, c) covers
    ``[c*cell, (c+1)*cell] x [r*cell, (r+1)*cell]`` m.
    """
    boxes = []
    for r, c, nr, nc in merge_cells(blocked):
        boxes.append({"box": {"center": [q((c + nc / 2) * cell), q((r + nr / 2) * cell)],
                              "size": [q(nc * cell), q(nr * cell)]}})
    return boxes


def world_skeleton(size: tuple[float, float], obstacles: list[dict[str, Any]]) -> WorldSpec:
    """A WorldSpec of the obstacles with placeholder start/goal (not checked), for geometry."""
    return WorldSpec.model_validate({"size": [q(size[0]), q(size[1])], "start": [0.0, 0.0],
                                     "goal": [0.0, 0.0], "obstacles": obstacles})


def pick_endpoints(world: WorldSpec, robot_radius: float | None = None, resolution: float = 0.05,
                   margin: float = 0.1, fixed: tuple[float, float] | None = None,
                   ) -> tuple[tuple[float, float], tuple[float, float]]:
    """A far-apart start and goal for a disc robot, chosen deterministically.

    Within the largest 8-connected component of the configuration space (cells whose centre
    keeps ``robot_radius`` (default: the default robot's) from every obstacle), take the two cells farthest apart by
    geodesic (8-connected grid) distance, approximated by a double sweep: the farthest cell A
    from an arbitrary cell, then the farthest cell B from A (exact on tree-like free space,
    close to the diameter in rooms and mazes). Only cells keeping ``robot_radius + margin``
    are candidates for A and B when the component has any, so the robot does not start
    touching a wall. With ``fixed`` (one end already chosen, m) the other end is the
    candidate farthest from it within its component.

    Returns:
        ``(A, B)`` in m (cell centres, rounded to 1e-6 m); ``(fixed, B)`` when fixed is given.
    Raises:
        InputError: the map has no room for the robot (near ``fixed``, when given).
    """
    robot_radius = default_robot_radius() if robot_radius is None else robot_radius
    geometry = static_geometry(world)
    raster = rasterize(geometry, resolution, inflate=robot_radius)
    roomy = ~rasterize(geometry, resolution, inflate=robot_radius + margin).occupied
    labels, count = ndimage.label(~raster.occupied, structure=EIGHT)
    where = f" near ({fixed[0]:g}, {fixed[1]:g})" if fixed is not None else ""
    problem = f"the map has no free space{where} for a robot of radius {robot_radius:g} m"
    if not count:
        raise InputError(problem)
    if fixed is None:
        sizes = np.bincount(labels.ravel())
        sizes[0] = 0
        component = labels == int(np.argmax(sizes))
    else:
        cell = free_cell_near(raster, fixed, robot_radius + resolution)
        if cell is None:
            raise InputError(problem)
        component = labels == labels[cell]
    candidates = component & roomy if (component & roomy).any() else component
    graph = grid_graph(~component)
    if fixed is None:
        seed = divmod(int(np.argmax(candidates)), candidates.shape[1])  # first candidate
        a = _farthest(grid_distances(~component, seed, graph=graph), candidates)
    else:
        a = cell
    b = _farthest(grid_distances(~component, a, graph=graph), candidates)
    sa, sb = raster.cell_center(*a), raster.cell_center(*b)
    first = (q(fixed[0]), q(fixed[1])) if fixed is not None else (q(sa[0]), q(sa[1]))
    return first, (q(sb[0]), q(sb[1]))


def _farthest(dist: np.ndarray, candidates: np.ndarray) -> tuple[int, int]:
    """The candidate cell with the largest finite distance (first in row-major order on ties)."""
    d = np.where(np.isfinite(dist) & candidates, dist, -1.0)
    r, c = divmod(int(np.argmax(d)), d.shape[1])
    return r, c
