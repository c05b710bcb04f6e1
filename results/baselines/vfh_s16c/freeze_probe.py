"""(Run with candidate_D_corner_slow.patch applied, from the tree's root.) At cycles of a trace, the point that sets VFH+'s corner speed limit: where it is
(odometry frame), its believed gap and closing rate, and the true gap to the walls there.
PYTHONPATH=$PWD python freeze_probe.py TRACE.npz T..."""
import math
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

from nav_bench.planners.vfh_plus import corner_speed_limit
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

rp = load(sys.argv[1])
p, s = rp.planner, rp.planner.settings
g = static_geometry(world_from_data(rp.meta["world"]))
looks = sorted(float(a) for a in sys.argv[2:])
for i in range(len(rp.t)):
    if rp.t[i] > looks[-1] + 1e-6:
        break
    obs = rp.obs(i)
    xy = rp.odom[i, :2].astype(float)
    yaw = float(rp.odom[i, 2])
    radius = min(s.window_radius, float(np.hypot(*(obs.goal - xy))))
    win = p._carved_window(obs, xy, radius) if any(abs(rp.t[i] - t) < 0.05 for t in looks) else None
    cmd = p.act(obs)
    if win is None:
        continue
    direction = p.k_prev * p.alpha
    b = win.bearings()
    v = corner_speed_limit(win, b, (yaw, direction), 0.18, s.mask_certainty, s.corner_slow_s)
    sure = win.certainty > s.mask_certainty
    closing = np.maximum(np.cos(b - yaw), np.cos(b - direction))
    lim = np.where(sure & (closing > 0), np.maximum(win.dist - 0.18, 0) / np.maximum(closing, 1e-9), np.inf)
    k = int(np.argmin(lim))
    pt = np.array([win.x[k], win.y[k]])
    true_gap_robot = float(clearance(g, rp.true[i:i + 1, :2].astype(float))[0]) - 0.18
    print(f"t={rp.t[i]:.1f} odom ({xy[0]:.2f},{xy[1]:.2f},{math.degrees(yaw):.0f}deg) cmd v {cmd.v:.3f} w {cmd.omega:.3f}; "
          f"limit {v:.4f} m/s from point ({pt[0]:.3f},{pt[1]:.3f}) dist {win.dist[k]:.3f} gap {win.dist[k] - 0.18:+.3f} "
          f"certainty {win.certainty[k]:.0f} bearing {math.degrees(math.remainder(b[k] - yaw, 2 * math.pi)):+.0f}deg "
          f"closing {closing[k]:.2f}; true gap of robot {true_gap_robot:+.3f}; "
          f"point's true clearance {float(clearance(g, pt[None])[0]):+.3f} (odom~true here)")
