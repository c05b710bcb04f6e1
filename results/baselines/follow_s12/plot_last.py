"""The last seconds of stored traces side by side (results/baselines/follow_s12/README.md).

    python results/baselines/follow_s12/plot_last.py OUT.png SECONDS TITLE1=TRACE1.npz [TITLE2=TRACE2.npz ...]

Each panel: the world's outlines, the true track of the last SECONDS s (grey: earlier), red
crosses where the command turned on the spot (v = 0, |omega| > 0.3 rad/s), the goal; zoomed on
the last SECONDS s. No simulation: the traces are read as stored.
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from nav_bench.episode.trace import Trace
from nav_bench.reporting.episode_plot import draw_outlines


def panel(ax, title: str, path: str, seconds: float) -> None:
    tr = Trace.load(path)
    xy, t, cmd = tr.true_pose[:, :2], tr.t, tr.cmd
    last = t >= t[-1] - seconds
    draw_outlines(ax, tr.world)
    ax.plot(xy[:, 0], xy[:, 1], color="0.8", lw=0.6)
    ax.plot(xy[last, 0], xy[last, 1], color="tab:blue", lw=1.0, label=f"last {seconds:.0f} s")
    spin = last & (np.abs(cmd[:, 0]) < 1e-6) & (np.abs(cmd[:, 1]) > 0.3)
    ax.scatter(xy[spin, 0], xy[spin, 1], s=12, marker="x", color="tab:red", label="turn on the spot", zorder=4)
    ax.plot(*tr.world.goal[:2], "r*", ms=12)
    c = xy[last].mean(axis=0)
    half = max(1.5, 0.6 * float(np.ptp(xy[last], axis=0).max()))
    ax.set_xlim(c[0] - half, c[0] + half)
    ax.set_ylim(c[1] - half, c[1] + half)
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=7)
    row = tr.row
    reason = f" ({row.get('stuck_reason')})" if row.get("stuck_reason") else ""
    ax.set_title(f"{title}: {row['outcome']}{reason} at {row['time_s']:.1f} s, "
                 f"{row['collisions']} contacts", fontsize=8)


def main() -> None:
    out, seconds, panels = sys.argv[1], float(sys.argv[2]), [a.split("=", 1) for a in sys.argv[3:]]
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 5), squeeze=False)
    for ax, (title, path) in zip(axes[0], panels, strict=True):
        panel(ax, title, path, seconds)
    fig.tight_layout()
    fig.savefig(out, dpi=100)


if __name__ == "__main__":
    main()
