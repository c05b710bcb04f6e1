"""Zoom on a contact: the true track of the SECONDS before it, coloured by planner mode.

usage: PYTHONPATH=<tree> python zoom.py OUT.png SECONDS NAME,TRACE.npz,REC.npz,T[,OTHER_TRACE.npz] ...

TRACE from ``nav-bench episode --trace``, REC from tbinstr.py (same episode), T the contact's
time (s). The red disc is the body (0.18 m) at the contact. OTHER_TRACE (optional): another
revision's trace of the same world, drawn in orange (its whole track) for comparison. A panel
whose T is not a contact of its own episode shows the pose at that time (the title says so).
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from nav_bench.episode.trace import Trace
from nav_bench.reporting.episode_plot import draw_outlines

COL = {0: ("tab:green", "motion to goal, goal free"), 1: ("tab:olive", "toward an endpoint"),
       2: ("tab:purple", "approach"), 3: ("tab:blue", "boundary following"), 4: ("tab:cyan", "strict lap"),
       5: ("k", "unreachable")}


def panel(ax, name, trace, rec, tc, seconds, other=None):
    tr = Trace.load(trace)
    z = np.load(rec)
    R = z["rec"]
    draw_outlines(ax, tr.world)
    m = (tr.t >= tc - seconds) & (tr.t <= tc + 0.3)
    xy = tr.true_pose[:, :2]
    ax.plot(xy[:, 0], xy[:, 1], color="0.85", lw=0.6)
    if other:
        o = Trace.load(other).true_pose[:, :2]
        ax.plot(o[:, 0], o[:, 1], color="tab:orange", lw=0.8, alpha=0.8, label="other revision, whole track")
    # modes by cycle: the trace rows and the record share the control cycles (nearest time)
    idx = np.clip(np.searchsorted(R[:, 0], tr.t[m]), 0, len(R) - 1)
    codes = R[idx, 4].astype(int)
    for c, (col, lab) in COL.items():
        k = codes == c
        if k.any():
            ax.scatter(xy[m][k, 0], xy[m][k, 1], s=6, color=col, label=lab, zorder=3)
    i = min(int(np.searchsorted(tr.t, tc + 0.1)), len(tr.t) - 1)
    p = tr.true_pose[i]
    ax.add_patch(plt.Circle((p[0], p[1]), 0.18, fill=False, color="tab:red", lw=1.2, zorder=4))
    ax.plot(*tr.world.goal[:2], "r*", ms=12)
    ax.set_xlim(p[0] - 1.5, p[0] + 1.5)
    ax.set_ylim(p[1] - 1.5, p[1] + 1.5)
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=6)
    what = "contact" if any(abs(c - tc) < 0.05 for c in z["contacts"].reshape(-1, 2)[:, 0]) else "no contact; pose"
    ax.set_title(f"{name}: {what} at {tc:.1f} s (red disc), {seconds:.0f} s before", fontsize=8)


def main():
    out, seconds = sys.argv[1], float(sys.argv[2])
    specs = [a.split(",") for a in sys.argv[3:]]  # name,trace.npz,rec.npz,t_contact
    fig, axes = plt.subplots(1, len(specs), figsize=(4.6 * len(specs), 4.8), squeeze=False)
    for ax, (name, trace, rec, tc, *other) in zip(axes[0], specs, strict=True):
        panel(ax, name, trace, rec, float(tc), seconds, other[0] if other else None)
    fig.tight_layout()
    fig.savefig(out, dpi=100)


if __name__ == "__main__":
    main()
