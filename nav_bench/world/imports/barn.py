"""Import a BARN world (Perille et al., "Benchmarking Metric Ground Navigation", SSRR 2020).

A BARN ``.world`` is Gazebo SDF 1.6 with static models ``unit_cylinder_N`` (radius
0.075 m, on a 0.15 m pitch, so neighbours touch). Only the ``<model>`` children of
``<world>`` that come *before* its ``<state>`` element are read (the state repeats them).

What the data shows (checked on the sample worlds): the cylinders fill x in [-4.5, 0] and
y in [0, 9.6] of the BARN frame. A full row of touching cylinders closes the bottom
(y ~ 0.075) and a full column each side (x ~ -4.425 and -0.075): these *are* the arena
walls. The 30 x 30 obstacle field of the BARN map sits in y ~ [5, 9.5]; the top is open,
the BARN protocol's goal (-2.25, 13.0) lies 3.5 m beyond it, the start (-2.25, 3.0)
(yaw 1.57 rad) is in the empty part below the field. Success is reaching within 1 m of the
goal in under 100 s.

Conversion: the world spans the cylinders' x extent and y from their lowest edge to
``goal_y + goal_margin_m``; the frame is shifted by ``(-xmin, -ymin)`` (recorded in meta as
``barn_to_world_offset``) so the arena walls coincide with the world's boundary walls.
Above the field the world is closed by the boundary at the arena's width, where BARN's
Gazebo floor is open; nothing there stands between the field and the goal.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np

from nav_bench.errors import InputError
from nav_bench.world.imports.grid import q

SOURCE = ("BARN dataset (Perille, Truong, Xiao, Stone, SSRR 2020), "
          "github.com/Daffan/the-barn-challenge jackal_helper/worlds/BARN")
LICENCE = "MIT (the-barn-challenge LICENSE)"
START = (-2.25, 3.0)  # BARN frame, m
START_YAW = 1.57  # rad, as in the BARN protocol
GOAL = (-2.25, 13.0)
GOAL_TOLERANCE_M = 1.0
TIME_LIMIT_S = 100.0
CELL = 0.15  # m, pitch of the BARN grid


def barn_path_to_xy(path_cells: np.ndarray) -> np.ndarray:
    """BARN path file cells (N, 2) int (row, col) -> (N, 2) m in the BARN frame.

    x = 0.15 row - 4.575, y = 0.15 col + 5.075 (the conversion of the BARN challenge).
    """
    cells = np.asarray(path_cells, dtype=float).reshape(-1, 2)
    return np.column_stack([CELL * cells[:, 0] - 4.575, CELL * cells[:, 1] + 5.075])


def read_barn_models(world_path: str | Path) -> tuple[list[tuple[float, float, float]],
                                                      list[tuple[float, float, float, float, float]]]:
    """Static cylinders ``(x, y, r)`` and boxes ``(cx, cy, sx, sy, yaw)`` of a Gazebo world (m, rad).

    Only models before ``<state>`` are read; the ground plane and models without collision
    geometry are skipped.
    """
    world_path = Path(world_path)
    if not world_path.is_file():
        raise InputError(f"{world_path}: BARN world file not found")
    try:
        root = ET.parse(world_path).getroot()
    except ET.ParseError as exc:
        raise InputError(f"{world_path}: not a readable SDF/XML file ({exc})") from None
    world = root.find("world") if root.tag == "sdf" else None
    if world is None:
        raise InputError(f"{world_path}: expected <sdf><world>...</world></sdf>")
    cylinders, boxes = [], []
    for child in world:
        if child.tag == "state":
            break  # the state section repeats the models
        if child.tag != "model":
            continue
        name = child.get("name", "?")
        pose_text = child.findtext("pose") or "0 0 0 0 0 0"
        try:
            pose = [float(v) for v in pose_text.split()]
        except ValueError:
            raise InputError(f"{world_path}: model {name!r} has an unreadable pose {pose_text!r}") from None
        x, y = pose[0], pose[1]
        yaw = pose[5] if len(pose) >= 6 else 0.0
        geometry = child.find("link/collision/geometry")
        if geometry is None:
            continue
        cyl, box = geometry.find("cylinder"), geometry.find("box")
        if cyl is not None:
            cylinders.append((x, y, float(cyl.findtext("radius", "0.075"))))
        elif box is not None:
            sx, sy = (float(v) for v in (box.findtext("size") or "0 0 0").split()[:2])
            boxes.append((x, y, sx, sy, yaw))
    if not cylinders and not boxes:
        raise InputError(f"{world_path}: no static cylinder or box models found")
    return cylinders, boxes


def import_barn(world_path: str | Path, path_file: str | Path | None = None, *,
                goal_margin_m: float = 1.5, name: str | None = None) -> dict[str, Any]:
    """A BARN world as world data (a dict ready for ``world_from_data``).

    Args:
        world_path: the BARN ``world_N.world`` file.
        path_file: optional ``path_N.npy``; its BARN reference length (start -> path cells ->
            goal, as the BARN challenge scores) is recorded in ``meta``.
        goal_margin_m: free space kept beyond the goal (m); the default covers the 1 m
            success radius.
        name: world name (default ``barn_<file stem>``).
    """
    world_path = Path(world_path)
    cylinders, boxes = read_barn_models(world_path)
    cyl = np.asarray(cylinders, dtype=float).reshape(-1, 3)
    bx = np.asarray(boxes, dtype=float).reshape(-1, 5)
    half = np.abs(np.cos(bx[:, 4])) * bx[:, 2] / 2 + np.abs(np.sin(bx[:, 4])) * bx[:, 3] / 2
    halfy = np.abs(np.sin(bx[:, 4])) * bx[:, 2] / 2 + np.abs(np.cos(bx[:, 4])) * bx[:, 3] / 2
    xmin = min(np.min(cyl[:, 0] - cyl[:, 2], initial=np.inf), np.min(bx[:, 0] - half, initial=np.inf))
    xmax = max(np.max(cyl[:, 0] + cyl[:, 2], initial=-np.inf), np.max(bx[:, 0] + half, initial=-np.inf))
    ymin = min(np.min(cyl[:, 1] - cyl[:, 2], initial=np.inf), np.min(bx[:, 1] - halfy, initial=np.inf))
    ox, oy = -float(xmin), -float(ymin)
    size = (float(xmax - xmin), GOAL[1] + oy + goal_margin_m)
    for what, (x, y) in (("start", START), ("goal", GOAL)):
        if not (0 < x + ox < size[0] and 0 < y + oy < size[1]):
            raise InputError(f"{world_path}: the BARN {what} ({x:g}, {y:g}) lies outside the "
                             f"obstacles' extent x in [{xmin:g}, {xmax:g}]; not a BARN world?")
    obstacles: list[dict[str, Any]] = [
        {"cylinder": {"center": [q(x + ox), q(y + oy)], "radius": q(r)}} for x, y, r in cyl]
    obstacles += [{"box": {"center": [q(x + ox), q(y + oy)], "size": [q(sx), q(sy)],
                           "yaw_deg": q(math.degrees(yaw))}} for x, y, sx, sy, yaw in bx]
    meta: dict[str, Any] = {
        "source": f"{SOURCE}/{world_path.name}",
        "licence": LICENCE,
        "imported_by": "nav-bench import barn",
        "barn_to_world_offset": [q(ox), q(oy)],
        "goal_tolerance_m": GOAL_TOLERANCE_M,
        "time_limit_s": TIME_LIMIT_S,
        "protocol": "BARN: start (-2.25, 3.0) yaw 1.57 rad, goal (-2.25, 13.0); success within "
                    "1 m of the goal without collision in under 100 s",
    }
    if path_file is not None:
        ref = reference_path(path_file)
        meta["reference_path_file"] = Path(path_file).name
        meta["reference_path_m"] = q(float(np.hypot(*np.diff(ref, axis=0).T).sum()))
    return {
        "name": name or f"barn_{world_path.stem}",
        "description": (f"BARN {world_path.stem}: {len(cyl)} cylinders of radius 0.075 m; "
                        "the BARN protocol's start and goal"),
        "size": [q(size[0]), q(size[1])],
        "boundary": True,
        "start": [q(START[0] + ox), q(START[1] + oy), q(math.degrees(START_YAW))],
        "goal": [q(GOAL[0] + ox), q(GOAL[1] + oy)],
        "obstacles": obstacles,
        "meta": meta,
    }


def reference_path(path_file: str | Path) -> np.ndarray:
    """BARN's reference path in the BARN frame (m): start, the path file's cells, goal."""
    path_file = Path(path_file)
    try:
        cells = np.load(path_file)
    except (OSError, ValueError) as exc:
        raise InputError(f"{path_file}: not a readable .npy path file ({exc})") from None
    if cells.ndim != 2 or cells.shape[1] != 2:
        raise InputError(f"{path_file}: expected an (N, 2) array of (row, col) cells, got {cells.shape}")
    return np.vstack([START, barn_path_to_xy(cells), GOAL])
