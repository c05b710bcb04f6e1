"""BARN-style clutter from a cellular automaton (Perille et al. 2020, "Benchmarking Metric
Ground Navigation", the BARN data set).

As in BARN's generator: a grid of ``grid`` cells of side ``cell`` (30 x 30 cells of 0.15 m
by default) is filled at random with probability ``fill``, its two side columns filled
(the side walls); then ``smoothing`` synchronous steps of the rule "a cell with more than
4 filled neighbours (of 8) becomes filled, one with fewer than 2 becomes empty" (cells
beyond the side walls count as filled, beyond the ends as empty) turn noise into blobs.

The robot crosses the clutter from bottom to top: the start lies in a free band of
``margin`` below the grid, the goal in one above it (outside the clutter, as in BARN).
With ``connect`` (BARN's own remedy) a blocked field is opened: the robot's footprint is a
k x k cell window (k = ceil((2 * robot_radius + 0.05) / cell), 3 for the defaults, BARN's
kernel), and the windows along the path from the bottom to the top edge that clears the
fewest filled cells (then the shortest) are emptied. BARN cuts an L-shaped corridor;
the fewest-cells path changes the map less. Without ``connect`` blocked layouts are
redrawn. The filled cells are written as few boxes (the importers' exact greedy
rectangle partition, :func:`nav_bench.world.imports.rectangles.merge_cells`: about 60
boxes for a default field instead of 200+ cells).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from nav_bench.errors import InputError
from nav_bench.world.generate.common import Setting, make_info
from nav_bench.world.imports.rectangles import merge_cells

SETTINGS = (
    Setting("grid", (30, 30), "cells", "cells across (x) and along (y, start to goal)", 5, 300),
    Setting("cell", 0.15, "m", "side of a grid cell (BARN: 0.15)", 0.0, 2.0, positive=True),
    Setting("fill", 0.25, "-", "initial probability that a cell is filled (BARN: 0.15 to 0.30)",
            0.0, 0.95),
    Setting("smoothing", 4, "-", "cellular-automaton smoothing steps (BARN: 2 to 4)", 0, 50),
    Setting("margin", 1.0, "m", "free band below the grid (start) and above it (goal)",
            0.0, 20.0, positive=True),
    Setting("connect", True, "-",
            "clear the fewest cells joining bottom and top for the robot (else redraw)"),
)

FOOTPRINT_MARGIN = 0.05  # m added to the robot's diameter when sizing its cell window


def smooth(filled: np.ndarray, steps: int) -> np.ndarray:
    """BARN's smoothing rule applied ``steps`` times to (H, W) bool ``filled`` (row = y)."""
    grid = filled.copy()
    kernel = np.ones((3, 3), dtype=int)
    kernel[1, 1] = 0
    for _ in range(steps):
        padded = np.pad(grid, 1, constant_values=False)
        padded[:, 0] = padded[:, -1] = True  # beyond the side walls counts as filled
        count = ndimage.convolve(padded.astype(int), kernel, mode="constant")[1:-1, 1:-1]
        grid = np.where(count > 4, True, np.where(count < 2, False, grid))
    return grid


def window_sums(filled: np.ndarray, k: int) -> np.ndarray:
    """(H-k+1, W-k+1) number of filled cells in each k x k window (summed-area table)."""
    s = np.pad(np.cumsum(np.cumsum(filled.astype(int), axis=0), axis=1), ((1, 0), (1, 0)))
    return s[k:, k:] - s[:-k, k:] - s[k:, :-k] + s[:-k, :-k]


def connect_bottom_top(filled: np.ndarray, k: int) -> np.ndarray:
    """``filled`` with cells cleared so a k x k window can slide from the bottom row to the top.

    Windows never include the side columns. If free windows already join the bottom and
    top edges (4-connected), nothing changes; otherwise Dijkstra over windows, entering a
    window costing 1 + 1000 x its filled cells, finds the path that clears the fewest cells.
    """
    h, w = filled.shape
    cost = window_sums(filled, k)[:, 1:w - k]  # window x-offsets 1 .. w-k-1
    hh, ww = cost.shape
    if hh < 1 or ww < 1:
        raise InputError(f"barn grid {w}x{h} is too small for a robot window of {k}x{k} cells")
    labels, _ = ndimage.label(cost == 0)
    if np.intersect1d(labels[0][labels[0] > 0], labels[-1][labels[-1] > 0]).size:
        return filled
    weight = 1.0 + 1000.0 * cost.astype(float)
    n = hh * ww
    idx = np.arange(n).reshape(hh, ww)
    src, dst = [], []
    for a, b in ((idx[:, :-1], idx[:, 1:]), (idx[:-1, :], idx[1:, :])):
        src += [a.ravel(), b.ravel()]
        dst += [b.ravel(), a.ravel()]
    source = n  # a virtual node joined to every bottom window
    src.append(np.full(ww, source))
    dst.append(idx[0])
    src_arr, dst_arr = np.concatenate(src), np.concatenate(dst)
    graph = coo_matrix((weight.ravel()[dst_arr], (src_arr, dst_arr)), shape=(n + 1, n + 1)).tocsr()
    dist, pred = dijkstra(graph, directed=True, indices=source, return_predecessors=True)
    node = int(idx[-1][np.argmin(dist[idx[-1]])])
    out = filled.copy()
    while node != source:
        r, c = divmod(node, ww)
        out[r:r + k, c + 1:c + 1 + k] = False
        node = int(pred[node])
    return out


def build(rng: np.random.Generator, s: dict[str, Any]) -> dict[str, Any]:
    """World data of one BARN-style field (see the module docstring)."""
    nx, ny = s["grid"]
    cell, margin = s["cell"], s["margin"]
    if margin < 2 * s["robot_radius"] + 0.1:
        raise InputError(f"barn setting 'margin' ({margin:g} m) must leave room for the robot "
                         f"at the start and goal: at least 2 x robot_radius + 0.1 = "
                         f"{2 * s['robot_radius'] + 0.1:g} m")
    filled = rng.random((ny, nx)) < s["fill"]
    filled[:, 0] = filled[:, -1] = True
    filled = smooth(filled, s["smoothing"])
    if s["connect"]:
        k = math.ceil((2 * s["robot_radius"] + FOOTPRINT_MARGIN) / cell)
        filled = connect_bottom_top(filled, k)
    obstacles = []
    for r0, c0, rows, cols in merge_cells(filled):
        obstacles.append({"box": {
            "center": [(c0 + cols / 2) * cell, margin + (r0 + rows / 2) * cell],
            "size": [cols * cell, rows * cell]}})
    sx, sy = nx * cell, ny * cell + 2 * margin
    return {
        "description": f"BARN-style cellular clutter, {nx}x{ny} cells of {cell:g} m, "
                       f"fill {s['fill']:g}, {s['smoothing']} smoothing steps",
        "size": [sx, sy],
        "start": [sx / 2, margin / 2, 90.0],
        "goal": [sx / 2, sy - margin / 2],
        "obstacles": obstacles,
    }


INFO = make_info("barn", "BARN-style cellular-automaton clutter (Perille et al. 2020); start "
                 "below, goal above the field.", SETTINGS, build)
