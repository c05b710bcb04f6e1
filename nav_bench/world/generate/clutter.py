"""Random clutter: boxes and cylinders scattered until they cover a fraction of the floor.

Shapes are drawn one by one (sizes uniform in their ranges, boxes at any yaw or
axis-aligned) and put at a random place where they stay ``min_gap`` from every other
shape and from the walls, and clear of discs of ``clear_radius`` around the start and the
goal (see :class:`~nav_bench.world.generate.placement.ShapePlacer`). Placement stops when
the shapes cover ``density`` of the floor or when 30 shapes in a row find no place; the
achieved density is written in the description. Random packing saturates: with the
default gap and sizes about 0.17 of the floor is the most that fits (0.2 with a 0.4 m
gap); ask for smaller shapes or a smaller gap for denser fields.

Because the shapes are convex and keep ``min_gap`` apart and from the walls, a robot
narrower than ``min_gap`` can always get round them: the default gap (0.5 m) guarantees a
reachable goal for the default robot (0.36 m wide). The start lies ``margin`` from the
left wall, the goal ``margin`` from the right one, at random heights.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from nav_bench.errors import InputError
from nav_bench.world.generate.common import Setting, make_info
from nav_bench.world.generate.placement import ShapeDraw, ShapePlacer, shape_obstacle

SETTINGS = (
    Setting("size", (10.0, 10.0), "m", "world size (x, y)", 1.0, 200.0),
    Setting("density", 0.15, "-", "fraction of the floor to cover with obstacles", 0.0, 0.7),
    Setting("min_gap", 0.5, "m", "least gap between obstacles and to the walls", 0.0, 10.0),
    Setting("box_size", (0.3, 1.2), "m", "range of box side lengths", 0.0, 20.0,
            ordered=True, positive=True),
    Setting("cylinder_radius", (0.15, 0.4), "m", "range of cylinder radii", 0.0, 10.0,
            ordered=True, positive=True),
    Setting("cylinder_fraction", 0.4, "-", "share of obstacles that are cylinders", 0.0, 1.0),
    Setting("aligned", False, "-", "boxes axis-aligned (else any yaw)"),
    Setting("margin", 1.0, "m", "start's distance from the left wall, goal's from the right",
            0.0, 100.0, positive=True),
    Setting("clear_radius", 0.8, "m", "no obstacle within this distance of the start or goal",
            0.0, 100.0),
)


def build(rng: np.random.Generator, s: dict[str, Any]) -> dict[str, Any]:
    """World data of one clutter field (see the module docstring)."""
    sx, sy = s["size"]
    m = s["margin"]
    if 2 * m >= sx or 2 * m >= sy:
        raise InputError(f"clutter setting 'margin' ({m:g} m) leaves no room in a "
                         f"{sx:g} x {sy:g} m world")
    start = (m, float(rng.uniform(m, sy - m)))
    goal = (sx - m, float(rng.uniform(m, sy - m)))
    placer = ShapePlacer(gap=s["min_gap"], keep_out_discs=np.array(
        [[*start, s["clear_radius"]], [*goal, s["clear_radius"]]]))
    draw = ShapeDraw(s["box_size"], s["cylinder_radius"], s["cylinder_fraction"], s["aligned"])
    area = placer.fill(rng, (0.0, 0.0, sx, sy), s["density"] * sx * sy, draw)
    return {
        "description": f"random clutter {sx:g} x {sy:g} m, density {s['density']:g} "
                       f"(achieved {area / (sx * sy):.3f}), gap {s['min_gap']:g} m",
        "size": [sx, sy],
        "start": list(start),
        "goal": list(goal),
        "obstacles": [shape_obstacle(shape) for shape in placer.placed],
    }


def covered_fraction(world_data: dict[str, Any]) -> float:
    """Fraction of the floor covered by the boxes and cylinders of ``world_data`` (their
    areas summed: exact when they do not overlap, as in clutter worlds)."""
    area = 0.0
    for ob in world_data.get("obstacles", []):
        if "box" in ob:
            area += ob["box"]["size"][0] * ob["box"]["size"][1]
        elif "cylinder" in ob:
            area += math.pi * ob["cylinder"]["radius"] ** 2
    sx, sy = world_data["size"]
    return area / (sx * sy)


INFO = make_info("clutter", "Random boxes and cylinders covering a given fraction of the "
                 "floor, kept a minimum gap apart.", SETTINGS, build)
