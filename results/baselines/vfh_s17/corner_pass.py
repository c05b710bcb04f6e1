"""corner_pass.py OUT.png T0 T1 X0 X1 Y0 Y1 TRACE.npz [TRACE.npz ...]: the true path of each
trace from T0 to T1 s in the box X0..X1, Y0..Y1 (m), one panel each: the body (0.18 m) every
0.5 s, cycles commanded v = 0 (a turn on the spot) in red, and the contact starts (true
clearance <= 1 mm) as black crosses. Titles: the trace's file name."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Circle

from nav_bench.world.draw import draw_world
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

RADIUS = 0.18  # m, the diffbot's body

out, t0, t1, x0, x1, y0, y1 = sys.argv[1], *map(float, sys.argv[2:8])
paths = sys.argv[8:]
fig, axes = plt.subplots(1, len(paths), figsize=(5.5 * len(paths), 5.5), squeeze=False)
for ax, path in zip(axes[0], paths, strict=True):
    trace = np.load(path, allow_pickle=True)
    world = world_from_data(json.loads(str(trace["meta"]))["world"])
    t, true, cmd = trace["t"], trace["true_pose"].astype(float), trace["cmd"]
    part = (t >= t0) & (t <= t1)
    draw_world(ax, world, show_start_goal=False)
    xy = true[part, :2]
    ax.plot(xy[:, 0], xy[:, 1], "-", color="tab:blue", lw=1)
    spot = part & (np.abs(cmd[:, 0]) < 1e-9)
    ax.plot(true[spot, 0], true[spot, 1], ".", color="red", ms=4, label="commanded v = 0")
    for i in np.flatnonzero(part)[::5]:
        ax.add_patch(Circle(true[i, :2], RADIUS, fill=False, lw=0.5, color="tab:blue", alpha=0.5))
    gap = clearance(static_geometry(world), true[:, :2]) - RADIUS
    starts = np.flatnonzero(part & (gap <= 1e-3) & np.concatenate([[True], gap[:-1] > 1e-3]))
    for i in starts:
        ax.add_patch(Circle(true[i, :2], RADIUS, fill=False, lw=1.5, color="black"))
        ax.plot(*true[i, :2], "kx")
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_title(f"{path.split('/')[-1][:40]}\n{t0:.0f}-{t1:.0f} s, least gap {gap[part].min() * 100:.1f} cm, "
                 f"{len(starts)} contact starts", fontsize=9)
    ax.legend(loc="lower right", fontsize=8)
fig.tight_layout()
fig.savefig(out, dpi=110)
print(out)
