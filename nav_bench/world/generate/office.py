"""Offices: a grid of rooms joined by doors, furnished with desks, cabinets and bins.

``rooms`` (nx, ny) rooms of free size ``room_size`` are separated by walls of
``wall_thickness``. Doors of ``door_width`` join the rooms along a random spanning tree of
the room grid (every room is reachable), plus a door in ``extra_doors`` of the remaining
shared walls (alternative routes); each door sits at a random place along its wall, at
least 0.2 m from the corners. Furniture (boxes, axis-aligned, and cylinders) covers
``furniture`` of each room's floor (as far as it fits); each piece keeps ``furniture_gap``
from the others and either the same from the walls or stands flush against one
(``against_wall`` of the boxes, like desks and cabinets), and never enters the zone ``door_clear`` deep on both sides of a door nor the
discs around the start and goal. The start is in the lower-left room, the goal in the
upper-right one. Walls are one segment per stretch between doors.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from nav_bench.errors import InputError
from nav_bench.world.generate.common import Setting, make_info
from nav_bench.world.generate.maze import spanning_tree_wilson
from nav_bench.world.generate.placement import ShapeDraw, ShapePlacer, shape_obstacle

SETTINGS = (
    Setting("rooms", (3, 2), "-", "rooms along x and y (nx, ny)", 1, 50),
    Setting("room_size", (4.0, 3.5), "m", "free size of a room (x, y)", 0.5, 50.0),
    Setting("wall_thickness", 0.1, "m", "thickness of the walls between rooms", 0.0, 1.0,
            positive=True),
    Setting("door_width", 0.9, "m", "free width of a door", 0.0, 10.0, positive=True),
    Setting("extra_doors", 0.3, "-",
            "share of the shared walls beyond the spanning tree that also get a door", 0.0, 1.0),
    Setting("furniture", 0.15, "-", "fraction of each room's floor covered by furniture",
            0.0, 0.6),
    Setting("furniture_gap", 0.5, "m", "least gap between furniture pieces and to the walls",
            0.0, 5.0),
    Setting("furniture_size", (0.4, 1.6), "m", "range of box (desk, cabinet) side lengths",
            0.0, 10.0, ordered=True, positive=True),
    Setting("against_wall", 0.6, "-", "share of boxes placed flush against a wall", 0.0, 1.0),
    Setting("cylinder_radius", (0.15, 0.3), "m", "range of cylinder (bin, pillar) radii",
            0.0, 5.0, ordered=True, positive=True),
    Setting("cylinder_fraction", 0.3, "-", "share of furniture pieces that are cylinders",
            0.0, 1.0),
    Setting("door_clear", 0.8, "m", "depth of the furniture-free zone on both sides of a door",
            0.0, 10.0),
    Setting("clear_radius", 0.6, "m", "no furniture within this distance of the start or goal",
            0.0, 10.0),
)

CORNER_CLEAR = 0.2  # m, a door keeps this much wall between itself and a corner


def _doors(rng: np.random.Generator, nx: int, ny: int, extra: float) -> list[tuple[int, int, int, int]]:
    """Room pairs ``(i, j, i2, j2)`` joined by a door: a spanning tree plus extras, sorted."""
    tree = {tuple(sorted([(i, j), (i2, j2)])) for i, j, i2, j2 in spanning_tree_wilson(rng, nx, ny)}
    others = sorted({tuple(sorted([(i, j), (i + di, j + dj)]))
                     for i in range(nx) for j in range(ny) for di, dj in ((1, 0), (0, 1))
                     if i + di < nx and j + dj < ny} - tree)
    n = round(extra * len(others))
    chosen = {others[int(k)] for k in rng.choice(len(others), size=n, replace=False)} if n else set()
    return [(*a, *b) for a, b in sorted(tree | chosen)]


def build(rng: np.random.Generator, s: dict[str, Any]) -> dict[str, Any]:
    """World data of one office (see the module docstring)."""
    nx, ny = s["rooms"]
    rw, rh = s["room_size"]
    t, dw = s["wall_thickness"], s["door_width"]
    if dw + 2 * CORNER_CLEAR > min(rw, rh) and nx * ny > 1:
        raise InputError(f"office setting 'door_width' ({dw:g} m) does not fit a room side of "
                         f"{min(rw, rh):g} m (needs door_width + {2 * CORNER_CLEAR:g} m)")
    if dw <= 2 * s["robot_radius"] and nx * ny > 1:
        raise InputError(f"office setting 'door_width' ({dw:g} m) must exceed the robot's "
                         f"diameter (2 x robot_radius = {2 * s['robot_radius']:g} m)")
    px, py = rw + t, rh + t
    sx, sy = nx * px - t, ny * py - t

    # door gaps per wall line: ("v", line) vertical line x = line*px - t/2, ("h", line) likewise
    gaps: dict[tuple[str, int], list[tuple[float, float]]] = {}
    door_zones = []
    for i, j, i2, j2 in _doors(rng, nx, ny, s["extra_doors"]):
        if j == j2:  # rooms side by side: a door in the vertical wall between them
            lo = j * py
            u = float(rng.uniform(lo + CORNER_CLEAR + dw / 2, lo + rh - CORNER_CLEAR - dw / 2))
            x = i2 * px - t / 2
            gaps.setdefault(("v", i2), []).append((u - dw / 2, u + dw / 2))
            door_zones.append([x, u, t + 2 * s["door_clear"], dw, 0.0])
        else:
            lo = i * px
            u = float(rng.uniform(lo + CORNER_CLEAR + dw / 2, lo + rw - CORNER_CLEAR - dw / 2))
            y = j2 * py - t / 2
            gaps.setdefault(("h", j2), []).append((u - dw / 2, u + dw / 2))
            door_zones.append([u, y, dw, t + 2 * s["door_clear"], 0.0])

    obstacles = []
    for axis, count, length in (("v", nx, sy), ("h", ny, sx)):
        for line in range(1, count):
            pos = line * (px if axis == "v" else py) - t / 2
            # wall ends are extended by t/2 when built, so stop t/2 short of each door edge
            cuts = [0.0]
            for a, b in sorted(gaps.get((axis, line), [])):
                cuts += [a - t / 2, b + t / 2]
            cuts.append(length)
            for a, b in zip(cuts[::2], cuts[1::2], strict=True):
                if b - a > 1e-9:
                    ends = ([pos, a], [pos, b]) if axis == "v" else ([a, pos], [b, pos])
                    obstacles.append({"wall": {"from": ends[0], "to": ends[1], "thickness": t}})

    start = (0.25 * rw, 0.5 * rh)
    goal = ((nx - 1) * px + 0.75 * rw, (ny - 1) * py + 0.5 * rh)
    placer = ShapePlacer(gap=s["furniture_gap"], keep_out_boxes=np.array(door_zones).reshape(-1, 5),
                         keep_out_discs=np.array([[*start, s["clear_radius"]],
                                                  [*goal, s["clear_radius"]]]))
    draw = ShapeDraw(s["furniture_size"], s["cylinder_radius"], s["cylinder_fraction"], True)
    area = 0.0
    for i in range(nx):
        for j in range(ny):
            region = (i * px, j * py, i * px + rw, j * py + rh)
            area += placer.fill(rng, region, s["furniture"] * rw * rh, draw,
                                flush_fraction=s["against_wall"])
    obstacles += [shape_obstacle(shape) for shape in placer.placed]
    return {
        "description": f"office, {nx}x{ny} rooms of {rw:g} x {rh:g} m, doors {dw:g} m, "
                       f"furniture {s['furniture']:g} (achieved {area / (nx * ny * rw * rh):.3f})",
        "size": [sx, sy],
        "start": list(start),
        "goal": list(goal),
        "obstacles": obstacles,
    }


INFO = make_info("office", "Rooms joined by doors (spanning tree plus extra doors) with "
                 "furniture that keeps doors clear.", SETTINGS, build)
