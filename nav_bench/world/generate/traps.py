"""The paper's trap families: a long wall with the goal behind it, U-shaped (concave) traps,
nested U's, and combs of dead-end bays.

These are the layouts the online re-planning paper names as hard for sensor-based
navigation (its Fig. 1, 4 and 5): a robot heading straight for the goal meets a concave
obstacle and must turn away from the goal, or pick one of two ways round a wall without
seeing which is shorter. Each family is a few parametrised walls; the seed draws the
free choices (which side, exact lengths within ``jitter``, which bay the robot faces).
The world is sized to fit the trap with free passages round it, the start lies 1 m from
one wall, the goal behind the trap, and the robot starts facing the goal.

* ``long_wall``: a wall across the way; the goal lies behind it towards one end
  (``side``, seen from the start facing the wall: left = +y). The short way round is on
  the goal's side unless ``offset`` moves the wall towards that side.
* ``u_trap``: a U whose cavity faces the start (the robot drives into the dead end) or
  away from it (``opening``); ``levels`` > 1 nests U's inside each other, ``spacing``
  apart, the recursive trap (each level is one more dead end to back out of).
* ``comb``: a spine wall with ``bays`` dead-end bays hanging from it, opening towards the
  start, the goal above the spine: the robot meets bay after bay on its way round.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from nav_bench.errors import InputError
from nav_bench.world.generate.common import Setting, make_info

EDGE = 1.0  # m, the start's distance from the left wall and the goal's from the far wall


def _wall(a: tuple[float, float], b: tuple[float, float], t: float) -> dict[str, Any]:
    return {"wall": {"from": list(a), "to": list(b), "thickness": t}}


def _jitter(rng: np.random.Generator, amount: float) -> float:
    return float(rng.uniform(-amount, amount)) if amount > 0 else 0.0


# --------------------------------------------------------------------------- long wall
LONG_WALL_SETTINGS = (
    Setting("wall_length", 8.0, "m", "length of the wall", 0.0, 200.0, positive=True),
    Setting("wall_distance", 3.0, "m", "from the start to the wall", 0.0, 100.0, positive=True),
    Setting("goal_distance", 1.5, "m", "from the wall to the goal, behind it", 0.0, 100.0,
            positive=True),
    Setting("side", "random", "-", "end of the wall the goal is nearer (left = +y, seen from "
            "the start)", choices=("left", "right", "random")),
    Setting("goal_shift", 2.0, "m", "sideways offset of the goal from the start, towards `side`",
            0.0, 100.0),
    Setting("offset", 0.0, "m", "sideways shift of the wall towards the goal's side "
            "(negative: away); moves the short way round", -100.0, 100.0),
    Setting("end_gap", 1.5, "m", "free passage between each wall end and the world's edge",
            0.0, 100.0, positive=True),
    Setting("thickness", 0.15, "m", "wall thickness", 0.0, 2.0, positive=True),
    Setting("jitter", 0.3, "m", "random change (+-) of the wall length, offset, distances and "
            "goal shift", 0.0, 10.0),
)


def build_long_wall(rng: np.random.Generator, s: dict[str, Any]) -> dict[str, Any]:
    """World data of one long-wall trap (see the module docstring)."""
    side = s["side"] if s["side"] != "random" else ("left", "right")[int(rng.integers(2))]
    sign = 1.0 if side == "left" else -1.0
    j = s["jitter"]
    length = max(0.5, s["wall_length"] + 2 * _jitter(rng, j))
    offset = s["offset"] + _jitter(rng, j)
    wall_distance = max(0.5, s["wall_distance"] + _jitter(rng, j))
    goal_distance = max(0.5, s["goal_distance"] + _jitter(rng, j))
    shift = max(0.0, s["goal_shift"] + _jitter(rng, j))
    t = s["thickness"]
    sy = length + 2 * s["end_gap"] + 2 * abs(offset)
    mid = sy / 2
    if shift > mid - 0.5:
        raise InputError(f"long_wall setting 'goal_shift' ({s['goal_shift']:g} m) puts the goal "
                         f"outside the world ({sy:.2f} m across); lower it or lengthen the wall")
    wall_x = EDGE + wall_distance
    wall_y = mid + sign * offset
    goal = (wall_x + goal_distance, mid + sign * shift)
    return {
        "description": f"long wall ({length:.1f} m), goal behind it towards the {side} end",
        "size": [goal[0] + EDGE, sy],
        "start": [EDGE, mid],
        "goal": list(goal),
        "obstacles": [_wall((wall_x, wall_y - length / 2), (wall_x, wall_y + length / 2), t)],
    }


# --------------------------------------------------------------------------- U trap
U_TRAP_SETTINGS = (
    Setting("depth", 3.0, "m", "inner depth of the innermost U", 0.0, 100.0, positive=True),
    Setting("width", 3.0, "m", "inner free width of the innermost U", 0.0, 100.0, positive=True),
    Setting("levels", 1, "-", "nested U's (each encloses the previous, `spacing` apart)", 1, 20),
    Setting("spacing", 1.0, "m", "free gap between nested U's", 0.0, 20.0, positive=True),
    Setting("opening", "start", "-", "cavity faces the start (a dead end on the way) or away",
            choices=("start", "away", "random")),
    Setting("approach", 2.0, "m", "from the start to the outermost U", 0.0, 100.0, positive=True),
    Setting("goal_distance", 1.5, "m", "from the outermost U to the goal, behind it",
            0.0, 100.0, positive=True),
    Setting("side_room", 1.5, "m", "free passage between the outermost U and the world's edge",
            0.0, 100.0, positive=True),
    Setting("thickness", 0.15, "m", "wall thickness", 0.0, 2.0, positive=True),
    Setting("jitter", 0.2, "m", "random change (+-) of depth, width and the trap's sideways "
            "position", 0.0, 10.0),
)


def build_u_trap(rng: np.random.Generator, s: dict[str, Any]) -> dict[str, Any]:
    """World data of one (nested) U trap (see the module docstring)."""
    opening = s["opening"] if s["opening"] != "random" else ("start", "away")[int(rng.integers(2))]
    j, t, levels, sp = s["jitter"], s["thickness"], s["levels"], s["spacing"]
    depth = max(0.3, s["depth"] + _jitter(rng, j))
    width = max(0.3, s["width"] + _jitter(rng, j))
    lateral = _jitter(rng, min(j, width / 4))  # keeps the start-goal line inside the cavity
    step = sp + t  # centre lines of nested walls are a gap plus a wall apart
    outer = levels - 1
    half_outer = width / 2 + t / 2 + outer * step  # centre-line half width, outermost U
    mouth_x = EDGE + s["approach"]  # outermost U's open end (opening: start)
    back_x = mouth_x + depth + t / 2 + 2 * outer * step  # outermost U's back wall
    sy = 2 * (half_outer + t / 2 + s["side_room"] + abs(lateral))
    yc = sy / 2 + lateral
    goal_x = back_x + t / 2 + s["goal_distance"]
    obstacles = []
    for k in range(levels):  # innermost first
        m = mouth_x + (outer - k) * step
        b = back_x - (outer - k) * step
        h = width / 2 + t / 2 + k * step
        if opening == "away":  # mirror the U inside its own extent: back faces the start
            m, b = mouth_x + back_x - m, mouth_x + back_x - b
        pts = [[m, yc - h], [b, yc - h], [b, yc + h], [m, yc + h]]
        obstacles.append({"polyline": {"points": pts, "thickness": t}})
    nested = f", {levels} nested" if levels > 1 else ""
    return {
        "description": f"U trap {depth:.1f} x {width:.1f} m{nested}, opening towards "
                       f"{'the start' if opening == 'start' else 'the goal'}",
        "size": [goal_x + EDGE, sy],
        "start": [EDGE, sy / 2],
        "goal": [goal_x, sy / 2],
        "obstacles": obstacles,
    }


# --------------------------------------------------------------------------- comb
COMB_SETTINGS = (
    Setting("bays", 4, "-", "number of dead-end bays", 1, 100),
    Setting("bay_depth", 2.0, "m", "mean depth of a bay (tooth length)", 0.0, 50.0, positive=True),
    Setting("tooth_spacing", 1.2, "m", "distance between neighbouring teeth (bay width)",
            0.0, 50.0, positive=True),
    Setting("approach", 2.0, "m", "from the start to the bays' mouths", 0.0, 100.0,
            positive=True),
    Setting("goal_distance", 1.5, "m", "from the spine to the goal, behind it", 0.0, 100.0,
            positive=True),
    Setting("side_room", 1.5, "m", "free passage beyond each end of the comb", 0.0, 100.0,
            positive=True),
    Setting("thickness", 0.15, "m", "wall thickness", 0.0, 2.0, positive=True),
    Setting("depth_jitter", 0.5, "m", "random change (+-) of each tooth's length", 0.0, 50.0),
)


def build_comb(rng: np.random.Generator, s: dict[str, Any]) -> dict[str, Any]:
    """World data of one comb of dead-end bays (see the module docstring)."""
    n, sp, t = s["bays"], s["tooth_spacing"], s["thickness"]
    teeth = [max(0.2, s["bay_depth"] + _jitter(rng, s["depth_jitter"])) for _ in range(n + 1)]
    x0 = s["side_room"]
    spine_y = EDGE + s["approach"] + max(teeth)
    sx = 2 * x0 + n * sp
    start_bay, goal_bay = (int(v) for v in rng.integers(0, n, 2))
    obstacles = [_wall((x0, spine_y), (x0 + n * sp, spine_y), t)]
    for i, length in enumerate(teeth):
        x = x0 + i * sp
        obstacles.append(_wall((x, spine_y - length), (x, spine_y), t))
    goal_y = spine_y + s["goal_distance"]
    return {
        "description": f"comb of {n} dead-end bays ({sp:g} m wide, ~{s['bay_depth']:g} m deep) "
                       "between start and goal",
        "size": [sx, goal_y + EDGE],
        "start": [x0 + (start_bay + 0.5) * sp, EDGE],
        "goal": [x0 + (goal_bay + 0.5) * sp, goal_y],
        "obstacles": obstacles,
    }


LONG_WALL = make_info("long_wall", "A long wall across the way with the goal behind it, "
                      "towards one end (paper, Fig. 1a/4).", LONG_WALL_SETTINGS, build_long_wall)
U_TRAP = make_info("u_trap", "A U-shaped (concave) trap, optionally nested U's (paper: large "
                   "concave and recursive U environments).", U_TRAP_SETTINGS, build_u_trap)
COMB = make_info("comb", "A comb of dead-end bays opening towards the start, the goal behind "
                 "the spine.", COMB_SETTINGS, build_comb)
