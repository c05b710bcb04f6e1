"""Grid mazes: perfect mazes (one path between any two cells), optionally with loops.

The maze has ``nx x ny`` square cells of free width ``corridor`` separated by walls of
``wall_thickness``; the world's boundary walls are the maze's outer walls. A perfect maze
is a random spanning tree of the cell grid, drawn by the recursive backtracker (a
depth-first search: long winding corridors, few branches) or by Wilson's algorithm
(loop-erased random walks: a uniformly random spanning tree, many short dead ends).
``loop_fraction`` then removes that fraction of the remaining interior walls, opening
cycles (a "braided" maze: several routes, harder for planners that remember visits).

Walls are merged into maximal straight segments along each grid line, so a 10 x 10 maze
is a few dozen walls rather than one per cell edge. The start is the centre of the
lower-left cell, the goal the centre of the upper-right one.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from nav_bench.errors import InputError
from nav_bench.world.generate.common import Setting, make_info, merge_runs

SETTINGS = (
    Setting("cells", (8, 8), "-", "cells along x and y (nx, ny)", 2, 200),
    Setting("corridor", 1.0, "m", "free width of a corridor (one cell)", 0.0, 20.0, positive=True),
    Setting("wall_thickness", 0.1, "m", "thickness of the maze walls", 0.0, 2.0, positive=True),
    Setting("algorithm", "backtracker", "-",
            "backtracker: depth-first, long corridors; wilson: uniform spanning tree, many dead ends",
            choices=("backtracker", "wilson")),
    Setting("loop_fraction", 0.0, "-",
            "fraction of the perfect maze's interior walls removed (0: one route only)", 0.0, 1.0),
)

_STEPS = ((1, 0), (-1, 0), (0, 1), (0, -1))


def spanning_tree_backtracker(rng: np.random.Generator, nx: int, ny: int) -> list[tuple[int, int, int, int]]:
    """Passages ``(i, j, i2, j2)`` of a depth-first (recursive backtracker) spanning tree."""
    visited = np.zeros((nx, ny), dtype=bool)
    start = (int(rng.integers(nx)), int(rng.integers(ny)))
    visited[start] = True
    stack = [start]
    passages = []
    while stack:
        i, j = stack[-1]
        options = [(i + di, j + dj) for di, dj in _STEPS
                   if 0 <= i + di < nx and 0 <= j + dj < ny and not visited[i + di, j + dj]]
        if not options:
            stack.pop()
            continue
        nxt = options[int(rng.integers(len(options)))]
        visited[nxt] = True
        passages.append((i, j, *nxt))
        stack.append(nxt)
    return passages


def spanning_tree_wilson(rng: np.random.Generator, nx: int, ny: int) -> list[tuple[int, int, int, int]]:
    """Passages of a uniformly random spanning tree (Wilson's loop-erased random walks)."""
    in_tree = np.zeros((nx, ny), dtype=bool)
    in_tree[int(rng.integers(nx)), int(rng.integers(ny))] = True
    order = rng.permutation(nx * ny)
    passages = []
    for flat in order:
        cell = (int(flat) // ny, int(flat) % ny)
        if in_tree[cell]:
            continue
        nxt: dict[tuple[int, int], tuple[int, int]] = {}  # last exit from each cell: erases loops
        c = cell
        while not in_tree[c]:
            options = [(c[0] + di, c[1] + dj) for di, dj in _STEPS
                       if 0 <= c[0] + di < nx and 0 <= c[1] + dj < ny]
            nxt[c] = options[int(rng.integers(len(options)))]
            c = nxt[c]
        c = cell
        while not in_tree[c]:
            in_tree[c] = True
            passages.append((*c, *nxt[c]))
            c = nxt[c]
    return passages


def maze_walls(rng: np.random.Generator, nx: int, ny: int, algorithm: str,
               loop_fraction: float) -> tuple[np.ndarray, np.ndarray]:
    """Interior walls of a maze.

    Returns:
        ``(horizontal, vertical)``: ``horizontal[j, i]`` (ny-1, nx) is the wall between cells
        (i, j) and (i, j+1); ``vertical[i, j]`` (nx-1, ny) the wall between (i, j) and (i+1, j).
    """
    horizontal = np.ones((ny - 1, nx), dtype=bool)
    vertical = np.ones((nx - 1, ny), dtype=bool)
    tree = spanning_tree_wilson if algorithm == "wilson" else spanning_tree_backtracker
    for i, j, i2, j2 in tree(rng, nx, ny):
        if j == j2:
            vertical[min(i, i2), j] = False
        else:
            horizontal[min(j, j2), i] = False
    if loop_fraction > 0:
        left = [("h", int(a), int(b)) for a, b in np.argwhere(horizontal)]
        left += [("v", int(a), int(b)) for a, b in np.argwhere(vertical)]
        n = round(loop_fraction * len(left))
        for k in rng.choice(len(left), size=n, replace=False) if n else ():
            kind, a, b = left[int(k)]
            (horizontal if kind == "h" else vertical)[a, b] = False
    return horizontal, vertical


def build(rng: np.random.Generator, s: dict[str, Any]) -> dict[str, Any]:
    """World data of one maze (see the module docstring)."""
    nx, ny = s["cells"]
    c, t = s["corridor"], s["wall_thickness"]
    if c <= 2 * s["robot_radius"]:
        raise InputError(f"maze setting 'corridor' ({c:g} m) must exceed the robot's diameter "
                         f"(2 x robot_radius = {2 * s['robot_radius']:g} m)")
    pitch = c + t
    sx, sy = nx * pitch - t, ny * pitch - t
    horizontal, vertical = maze_walls(rng, nx, ny, s["algorithm"], s["loop_fraction"])

    def span(first: int, last: int, limit: float) -> tuple[float, float]:
        # a run of edges from cell `first` to `last` reaches the wall posts at both its ends
        return max(0.0, first * pitch - t / 2), min(limit, (last + 1) * pitch - t / 2)

    obstacles = []
    for line, first, last in merge_runs(horizontal):
        y = (line + 1) * pitch - t / 2
        a, b = span(first, last, sx)
        obstacles.append({"wall": {"from": [a, y], "to": [b, y], "thickness": t}})
    for line, first, last in merge_runs(vertical):
        x = (line + 1) * pitch - t / 2
        a, b = span(first, last, sy)
        obstacles.append({"wall": {"from": [x, a], "to": [x, b], "thickness": t}})
    loops = f", {s['loop_fraction']:g} of walls removed" if s["loop_fraction"] else ""
    return {
        "description": f"{s['algorithm']} maze, {nx}x{ny} cells, corridor {c:g} m{loops}",
        "size": [sx, sy],
        "start": [c / 2, c / 2],
        "goal": [(nx - 1) * pitch + c / 2, (ny - 1) * pitch + c / 2],
        "obstacles": obstacles,
    }


INFO = make_info("maze", "Grid maze (recursive backtracker or Wilson), optionally with loops; "
                 "start and goal in opposite corner cells.", SETTINGS, build)
