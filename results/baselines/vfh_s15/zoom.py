"""A close-up of a VFH+ gap ending: the true obstacles (grey), the line the robot's centre
cannot cross with VFH+'s enlargement r_rs = 0.23 m (red dashed: clearance = r_rs), the true
trajectory from T0 s on (blue), the widest route from the trajectory's last point (green,
vfh_s14/gapwhy.widest_route), the two-sided constriction (black dot) and the route point the
fourteenth session took for the gap (orange cross). Metres, world frame.
PYTHONPATH=$PWD python results/baselines/vfh_s15/zoom.py TRACE.npz OUT.png --box X0 X1 Y0 Y1
    --at X Y --s14 X Y [--from T0]
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
sys.path.insert(0, "results/baselines/vfh_s14")
from gapwhy import widest_route
from trace_replay import load

from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

R_RS = 0.23  # m, robot radius 0.18 + safety_distance 0.05

ap = argparse.ArgumentParser()
ap.add_argument("trace")
ap.add_argument("out")
ap.add_argument("--box", type=float, nargs=4, required=True)
ap.add_argument("--at", type=float, nargs=2, required=True)
ap.add_argument("--s14", type=float, nargs=2, required=True)
ap.add_argument("--from", dest="t0", type=float, default=0.0)
a = ap.parse_args()
replay = load(a.trace)
world = world_from_data(replay.meta["world"])
g = static_geometry(world)
x0, x1, y0, y1 = a.box
xs, ys = np.meshgrid(np.arange(x0, x1, 0.01), np.arange(y0, y1, 0.01))
c = clearance(g, np.stack([xs.ravel(), ys.ravel()], 1)).reshape(xs.shape)
fig, ax = plt.subplots(figsize=(7, 7 * (y1 - y0) / (x1 - x0)))
ax.contourf(xs, ys, c, levels=[-10, 0], colors=["0.55"])
ax.contour(xs, ys, c, levels=[R_RS], colors=["red"], linestyles="dashed", linewidths=1)
keep = replay.t >= a.t0
ax.plot(*replay.true[keep, :2].T, color="tab:blue", lw=0.8, label=f"true trajectory from {a.t0:.0f} s")
end = tuple(replay.true[-1, :2])
way = widest_route(g, end, tuple(world.goal))[0][1]
ax.plot(*way.T, color="tab:green", lw=1.5, label="widest route to the goal")
gap = 2 * float(clearance(g, np.asarray([a.at]))[0])
ax.plot(*a.at, "ko", label=f"constriction, {gap:.3f} m")
ax.plot(*a.s14, "x", color="tab:orange", ms=10, mew=2, label="vfh_s14's 'gap' (route hugs one obstacle)")
ax.plot([], [], "r--", lw=1, label="clearance = r_rs 0.23 m (VFH+'s enlarged robot)")
ax.set_xlim(x0, x1)
ax.set_ylim(y0, y1)
ax.set_aspect("equal")
ax.set_xlabel("x [m]")
ax.set_ylabel("y [m]")
ax.set_title(f"{replay.meta['row']['world']}: VFH+ (main), {replay.meta['row']['outcome']} at {replay.t[-1]:.1f} s")
ax.legend(loc="lower left", fontsize=7, framealpha=0.9)
fig.tight_layout()
fig.savefig(a.out, dpi=110)
