"""Import a MovingAI grid map (``.map``) and a scenario line (``.scen``) as a world.

Format (Sturtevant, "Benchmarks for Grid-Based Pathfinding", IEEE TCIAIG 2012;
https://movingai.com/benchmarks/): header ``type octile`` / ``height H`` / ``width W`` /
``map``, then H lines of W characters; ``.`` and ``G`` are passable, every other character
blocked. A ``.scen`` file has a ``version`` line, then tab-separated lines ``bucket map
width height start_x start_y goal_x goal_y optimal_length``; x is the column, y the row
with row 0 the *first* map line; the optimal length is in cells for 8-connected moves
(1 / sqrt 2, no corner cutting).

The world has row 0 at the *bottom*, so map line ``y`` becomes world row ``H - 1 - y``, and
a cell of side ``cell`` m: cell (x, y) has its centre at ``((x + 0.5) cell,
(H - 1 - y + 0.5) cell)``. Blocked cells are merged into few boxes.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from nav_bench.errors import InputError
from nav_bench.world.imports.grid import blocked_to_boxes, pick_endpoints, q, world_skeleton

PASSABLE = frozenset(".G")
SOURCE = "MovingAI grid benchmarks, https://movingai.com/benchmarks/ (Sturtevant, IEEE TCIAIG 2012)"
LICENCE = "Open Data Commons Attribution License (ODC-By 1.0)"


@dataclass(frozen=True)
class Scenario:
    """One ``.scen`` line: cells as (x = column, y = row from the top), optimal length in cells."""

    bucket: int
    map_name: str
    width: int
    height: int
    start: tuple[int, int]
    goal: tuple[int, int]
    optimal: float
    line: int  # 1-based line in the file


def read_movingai_map(path: str | Path) -> np.ndarray:
    """(H, W) bool, True = blocked, row 0 = the first map line (MovingAI's y = 0)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: MovingAI map not found")
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    header: dict[str, str] = {}
    i = 0
    while i < len(lines) and lines[i].strip().lower() != "map":
        parts = lines[i].split()
        if len(parts) == 2:
            header[parts[0].lower()] = parts[1]
        elif parts:
            raise InputError(f"{path}:{i + 1}: expected a header line 'key value' or 'map', "
                             f"got {lines[i]!r}")
        i += 1
    if i == len(lines):
        raise InputError(f"{path}: no 'map' line; expected a MovingAI header "
                         "(type octile, height H, width W, map)")
    try:
        h, w = int(header["height"]), int(header["width"])
    except (KeyError, ValueError):
        raise InputError(f"{path}: the header needs integer 'height' and 'width' lines") from None
    rows = [line.rstrip("\r\n") for line in lines[i + 1:i + 1 + h]]
    if len(rows) != h:
        raise InputError(f"{path}: expected {h} map lines after 'map', found {len(rows)}")
    for k, row in enumerate(rows):
        if len(row) < w:
            raise InputError(f"{path}:{i + 2 + k}: expected {w} characters, found {len(row)}")
    chars = np.array([list(row[:w]) for row in rows])
    return ~np.isin(chars, list(PASSABLE))


def read_scen(path: str | Path) -> list[Scenario]:
    """All scenario lines of a ``.scen`` file (version 1 format)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: MovingAI scenario file not found")
    out = []
    for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
        if not line.strip() or line.lower().startswith("version"):
            continue
        f = line.split("\t") if "\t" in line else line.split()
        if len(f) != 9:
            raise InputError(f"{path}:{n}: expected 9 tab-separated fields "
                             f"(bucket map width height sx sy gx gy length), found {len(f)}")
        try:
            out.append(Scenario(int(f[0]), f[1], int(f[2]), int(f[3]), (int(f[4]), int(f[5])),
                                (int(f[6]), int(f[7])), float(f[8]), n))
        except ValueError:
            raise InputError(f"{path}:{n}: could not read numbers in {line!r}") from None
    return out


def scen_cell_to_world(xy: tuple[int, int], height: int, cell: float) -> tuple[float, float]:
    """Centre (m) of MovingAI cell (x = column, y = row from the top) in the world frame."""
    return q((xy[0] + 0.5) * cell), q((height - 1 - xy[1] + 0.5) * cell)


def import_movingai(map_path: str | Path, scen: str | Path | None = None, index: int = 0,
                    cell: float = 0.5, *, robot_radius: float | None = None,
                    name: str | None = None) -> dict[str, Any]:
    """A MovingAI map as world data (a dict ready for ``world_from_data``).

    Args:
        map_path: the ``.map`` file.
        scen: a ``.scen`` file; start and goal come from its scenario ``index`` (0 = the first
            line after ``version``). Without it a far-apart pair is picked automatically
            (:func:`~nav_bench.world.imports.grid.pick_endpoints`).
        cell: side of a map cell in the world (m).
        robot_radius: disc radius used to pick start/goal automatically (m); default: the
            default robot's.
        name: world name (default ``<map stem>_<index>`` with a scenario, else the stem).
    """
    map_path = Path(map_path)
    if not cell > 0:
        raise InputError(f"cell must be a positive number of metres, got {cell!r}")
    blocked_top = read_movingai_map(map_path)
    h, w = blocked_top.shape
    blocked = blocked_top[::-1]  # world row 0 = bottom = last map line
    obstacles = blocked_to_boxes(blocked, cell)
    size = (w * cell, h * cell)
    meta: dict[str, Any] = {"source": f"{SOURCE}; map {map_path.name}", "licence": LICENCE,
                            "imported_by": "nav-bench import movingai", "cell_m": cell,
                            "cells": [w, h]}
    if scen is not None:
        scenarios = read_scen(scen)
        if not 0 <= index < len(scenarios):
            raise InputError(f"{scen}: scenario index {index} out of range "
                             f"(the file has {len(scenarios)} scenarios, 0..{len(scenarios) - 1})")
        sc = scenarios[index]
        if (sc.width, sc.height) != (w, h):
            raise InputError(f"{scen}:{sc.line}: scenario is for a {sc.width}x{sc.height} map, "
                             f"{map_path.name} is {w}x{h}")
        for what, (x, y) in (("start", sc.start), ("goal", sc.goal)):
            if not (0 <= x < w and 0 <= y < h) or blocked_top[y, x]:
                raise InputError(f"{scen}:{sc.line}: {what} cell (x={x}, y={y}) is outside the map "
                                 f"or blocked in {map_path.name}")
        start, goal = scen_cell_to_world(sc.start, h, cell), scen_cell_to_world(sc.goal, h, cell)
        meta.update({"scen_file": Path(scen).name, "scen_index": index, "scen_bucket": sc.bucket,
                     "scen_start_xy": list(sc.start), "scen_goal_xy": list(sc.goal),
                     "scen_optimal_cells": sc.optimal, "scen_optimal_m": q(sc.optimal * cell)})
        default_name = f"{map_path.stem}_{index}"
        what = f"scenario {index} (bucket {sc.bucket}, octile optimum {sc.optimal:g} cells)"
    else:
        start, goal = pick_endpoints(world_skeleton(size, obstacles), robot_radius)
        meta["start_goal"] = "automatic"
        default_name, what = map_path.stem, "start and goal picked automatically"
    return {
        "name": name or default_name,
        "description": f"MovingAI map {map_path.stem} ({w}x{h} cells of {cell:g} m), {what}",
        "size": [q(size[0]), q(size[1])],
        "boundary": True,
        "start": list(start),
        "goal": list(goal),
        "obstacles": obstacles,
        "meta": meta,
    }
