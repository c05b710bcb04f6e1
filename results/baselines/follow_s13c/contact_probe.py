"""Where are an episode's contacts, and was the gap axis steering just before them?

    PYTHONPATH=TREE python contact_probe.py WORLD PLANNER TLIMIT

Replays one episode of results/baselines/bugs_s6/worlds/WORLD.yaml with the candidate's
``WallFollower._axis_clear`` logged (time, passed), finds the contacts from the true pose and the
world file (clearance of the 0.18 m body < 0) and prints, for each contact, the gap checks of
the 3 s before it. Writes the trace to /tmp/s13folc/WORLD_PLANNER.npz.
"""

import contextlib
import io
import json
import math
import sys

import numpy as np
import yaml

from nav_bench.cli import main
from nav_bench.planners import follow

RADIUS = 0.18  # m: the diffbot's body


def box_distance(x: float, y: float, box: dict) -> float:
    """Distance (m) from (x, y) to a yawed box's outline (negative inside)."""
    a = math.radians(box.get("yaw_deg", 0.0))
    dx, dy = x - box["center"][0], y - box["center"][1]
    u, v = dx * math.cos(a) + dy * math.sin(a), -dx * math.sin(a) + dy * math.cos(a)
    ox, oy = abs(u) - box["size"][0] / 2, abs(v) - box["size"][1] / 2
    return math.hypot(max(ox, 0.0), max(oy, 0.0)) + min(max(ox, oy), 0.0)


def wall_distance(x: float, y: float, wall: dict) -> float:
    """Distance (m) from (x, y) to a wall segment of some thickness."""
    (ax, ay), (bx, by) = wall["from"], wall["to"]
    vx, vy = bx - ax, by - ay
    k = max(0.0, min(1.0, ((x - ax) * vx + (y - ay) * vy) / max(vx * vx + vy * vy, 1e-12)))
    return math.hypot(x - ax - k * vx, y - ay - k * vy) - wall["thickness"] / 2


def clearance(world: dict, x: float, y: float) -> float:
    """Clearance (m) of the robot body at (x, y) from the room walls and obstacles."""
    sx, sy = world["size"]
    c = min(x, y, sx - x, sy - y)
    for o in world["obstacles"]:
        if "cylinder" in o:
            q = o["cylinder"]
            c = min(c, math.hypot(x - q["center"][0], y - q["center"][1]) - q["radius"])
        elif "wall" in o:
            c = min(c, wall_distance(x, y, o["wall"]))
        else:
            c = min(c, box_distance(x, y, o["box"]))
    return c - RADIUS


def run() -> None:
    world, planner, limit = sys.argv[1:4]
    log: list[tuple[float, bool]] = []
    original = follow.WallFollower._axis_clear

    def logged(self, obs, heading):
        clear = original(self, obs, heading)
        log.append((float(obs.t), bool(clear)))
        return clear

    follow.WallFollower._axis_clear = logged
    path = f"results/baselines/bugs_s6/worlds/{world}.yaml"
    trace = f"/tmp/s13folc/{world}_{planner}.npz"
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        main(["episode", path, "--planner", planner, "--seed", "0", "--time-limit", limit, "--json",
              "--trace", trace])
    row = json.loads(out.getvalue())
    print(world, planner, row["outcome"], row.get("stuck_reason"), "collisions", row["collisions"],
          "checks", len(log), "clear", sum(c for _, c in log))
    with open(path) as fh:
        spec = yaml.safe_load(fh)
    z = np.load(trace, allow_pickle=True)
    t, poses = z["t"], z["true_pose"]
    cl = np.array([clearance(spec, p[0], p[1]) for p in poses])
    inside = set(np.nonzero(cl < 0.0)[0].tolist())
    for i in sorted(i for i in inside if i - 1 not in inside):
        near = [(tt, c) for tt, c in log if t[i] - 3 <= tt <= t[i]]
        print(f"contact t={t[i]:.1f} at ({poses[i, 0]:.2f},{poses[i, 1]:.2f}) min clr {cl[i:i + 20].min():.3f};"
              f" gap checks in the 3 s before: {len(near)}, passed {sum(c for _, c in near)}")


if __name__ == "__main__":
    run()
