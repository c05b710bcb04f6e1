"""Check the argument behind the fix on stored traces: for every Bug2 lap that closed at its
hit point H (an ``unreachable`` event on main, ``unreachable`` or ``lap`` on the branch), did the
lap cross the open segment (H, goal], and does the closed lap (its path plus the step back to
H) wind round the goal? Also: which of the world's obstacles lie inside the lap.

    python lap_geometry.py TRACES_DIR [TRACES_DIR ...]

Reads ``meta`` (events, world) and ``odom_pose`` (the pose the planner saw) of each ``*.npz``
under the folders; prints one line per closed lap. Units: m, rad.
"""

from __future__ import annotations

import ast
import json
import math
import sys
from pathlib import Path

import numpy as np


def crossings(path: np.ndarray, h: np.ndarray, goal: np.ndarray) -> list[float]:
    """Parameters s in (0, 1] (0 = H, 1 = goal) where the polyline ``path`` (N, 2) crosses the
    segment from ``h`` to ``goal``; a touch at H itself (s < 1e-3) is not a crossing."""
    d = goal - h
    n = np.array([-d[1], d[0]]) / np.hypot(*d)  # left normal of H->goal
    off = (path - h) @ n
    out = []
    for i in range(len(path) - 1):
        a, b = off[i], off[i + 1]
        if a == b or ((a > 0) == (b > 0) and a != 0 and b != 0):
            continue
        f = a / (a - b)
        p = path[i] + f * (path[i + 1] - path[i])
        s = float((p - h) @ d / (d @ d))
        if 1e-3 < s <= 1.0:
            out.append(s)
    return out


def winding(path: np.ndarray, centre: np.ndarray) -> int:
    """Winding number of the closed polygon ``path`` (last point joined to the first) round
    ``centre``."""
    closed = np.vstack([path, path[:1]])
    ang = np.arctan2(closed[:, 1] - centre[1], closed[:, 0] - centre[0])
    return round(float(np.sum(np.remainder(np.diff(ang) + math.pi, 2 * math.pi) - math.pi)) / (2 * math.pi))


def obstacle_centres(world: dict) -> list[tuple[str, np.ndarray]]:
    """(label, centre) of each obstacle of the world spec (boxes, cylinders, walls' midpoints)."""
    out = []
    for ob in world.get("obstacles", []):
        kind, spec = next(iter(ob.items()))
        if "center" in spec:
            out.append((f"{kind} {spec['center']}", np.asarray(spec["center"][:2], float)))
        elif "from" in spec:
            c = (np.asarray(spec["from"], float) + np.asarray(spec["to"], float)) / 2
            out.append((f"{kind} {spec['from']}-{spec['to']}", c))
    return out


def inside(poly: np.ndarray, p: np.ndarray) -> bool:
    return winding(poly, p) != 0


def laps(trace: Path):
    with np.load(trace, allow_pickle=True) as d:
        meta = json.loads(str(d["meta"]))
        t, pose = d["t"], d["odom_pose"][:, :2].astype(float)
    events = ast.literal_eval(meta["events"]) if isinstance(meta["events"], str) else meta["events"]
    world = ast.literal_eval(meta["world"]) if isinstance(meta["world"], str) else meta["world"]
    goal = np.asarray(world["goal"][:2], float)
    hit = None
    for ev in events:
        if ev["kind"] == "replan" and ev["data"].get("reason") == "hit":
            hit = ev
        elif ev["kind"] in ("unreachable", "lap") and hit is not None:
            h = np.array([hit["data"]["x"], hit["data"]["y"]])
            sel = (t >= hit["t"] - 1e-9) & (t <= ev["t"] + 1e-9)
            path = np.vstack([h, pose[sel]])
            cr = crossings(path, h, goal)
            w = winding(np.vstack([path, h]), goal)
            enclosed = [label for label, c in obstacle_centres(world) if inside(path, c)]
            yield ev["kind"], hit["t"], ev["t"], h, cr, w, enclosed, float(np.hypot(*(goal - h)))


def main(folders: list[str]) -> None:
    for folder in folders:
        for trace in sorted(Path(folder).glob("*.npz")):
            if "__bug2__" not in trace.name:
                continue
            for kind, t0, t1, h, cr, w, enclosed, dist in laps(trace):
                cross = ", ".join(f"{s:.2f} ({s * dist:.2f} m from H)" for s in cr) or "none"
                print(f"{trace.name.rsplit('__', 1)[0]:36s} {kind:11s} H=({h[0]:.2f}, {h[1]:.2f}) "
                      f"t {t0:.1f}-{t1:.1f} s  crossings of (H, goal] at s = {cross}  "
                      f"winding round goal {w}  inside the lap: {'; '.join(enclosed) or 'no obstacle centre'}")


if __name__ == "__main__":
    main(sys.argv[1:])
