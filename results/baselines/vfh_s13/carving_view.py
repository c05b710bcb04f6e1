"""What the carving changes at a gap: a VFH+ trace replayed through a fresh planner of this
branch; at the cycle (within ``--near`` m of the gap's midpoint) where the histogram toward
the midpoint drops most from whole cells to kept parts, draw the map near the gap (cells
with certainty > 0, their kept parts, the true obstacles, the robot) and both histograms.

PYTHONPATH=$PWD python results/baselines/vfh_s13/carving_view.py TRACE.npz MX MY OUT.png [--near 1.0]
"""
from __future__ import annotations

import argparse
import math
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.patches import Circle, Rectangle

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

from nav_bench.planners.carving import CARVE_MEMORY_S, PARTS
from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import active_cells, polar_histogram, read_window
from nav_bench.world.draw import draw_world
from nav_bench.world.load import world_from_data


def whole_cells(p, xy):
    """(cells (M, 2), certainty (M,), H^p (n,)) of the planner's grid read as whole cells."""
    s = p.settings
    cells, cert = active_cells(p.grid.values(), p.frame, xy, s.window_radius, s.c_max)
    return cells, cert, polar_histogram(cells, cert, xy, p.n, 0.18 + s.safety_distance, s.window_radius,
                                        s.distance_weight)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("trace")
    ap.add_argument("mx", type=float)
    ap.add_argument("my", type=float)
    ap.add_argument("out")
    ap.add_argument("--near", type=float, default=1.0)
    ap.add_argument("--at", type=float, default=None, help="draw this time (s) instead")
    a = ap.parse_args()
    replay = load(a.trace)
    p, mid = replay.planner, np.array([a.mx, a.my])
    best, first = None, None
    s = p.settings
    for i in range(len(replay.t) if a.at is None else 0):
        p.act(replay.obs(i))
        xy = replay.odom[i, :2]
        d = float(np.hypot(*(mid - xy)))
        if d > a.near or d < a.near / 2:
            continue
        k = round((math.atan2(mid[1] - xy[1], mid[0] - xy[0]) % (2 * math.pi)) / p.alpha) % p.n
        _, _, whole = whole_cells(p, xy)
        drop = whole[k] - p.primary[k]
        if best is None or drop > best[0]:
            best = (drop, i)
        if whole[k] > s.threshold_high and p.primary[k] < s.threshold_low:
            first = i  # the grid closes the gap's direction, the kept parts leave it free
            break
    if a.at is not None:
        i = int(np.argmin(np.abs(replay.t - a.at)))
    elif best is None:
        sys.exit("the robot never came that near the midpoint")
    else:
        i = best[1] if first is None else first
    replay = load(a.trace)  # again, up to that cycle, to draw its state
    p = replay.planner
    for j in range(i + 1):
        p.act(replay.obs(j))
    xy = replay.odom[i, :2]
    cells, cert, whole = whole_cells(p, xy)
    radius = p.settings.window_radius
    window = read_window(p.grid.values(), p.frame, xy, radius, p.settings.c_max)
    flat = window.rows * p.frame.cols + window.cols
    kept_all = p.carving.carved_t.reshape(-1, PARTS)[flat] < replay.t[i] - CARVE_MEMORY_S
    parts = cell_parts(np.stack([window.x, window.y], axis=1), p.frame.cell)
    world = world_from_data(replay.meta["world"])
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5.2))
    draw_world(ax, world)
    for (cx, cy), c in zip(cells, cert, strict=True):
        ax.add_patch(Rectangle((cx - 0.05, cy - 0.05), 0.1, 0.1, fill=False, color=str(0.7 - 0.6 * c / 15), lw=0.6))
    kp = parts[kept_all]
    gone = parts[~kept_all]
    ax.plot(kp[:, 0], kp[:, 1], ".", ms=2, color="k", label="kept parts")
    ax.plot(gone[:, 0], gone[:, 1], ".", ms=2, color="#d62728", label="parts seen through (2 views)")
    ax.add_patch(Circle(xy, 0.18, fill=False, color="#1f77b4", lw=1.5))
    ax.add_patch(Circle(xy, 0.23, fill=False, color="#1f77b4", lw=0.8, ls=":"))
    ax.plot(*mid, "x", color="#2ca02c", ms=8, label="gap midpoint")
    ax.plot(replay.true[: i + 1, 0], replay.true[: i + 1, 1], color="#1f77b4", lw=1, alpha=0.6)
    ax.set_xlim(xy[0] - radius - 0.2, xy[0] + radius + 0.2)
    ax.set_ylim(xy[1] - radius - 0.2, xy[1] + radius + 0.2)
    ax.set_aspect("equal")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    ax.set_title(f"{replay.meta['row']['world']} t = {replay.t[i]:.1f} s: grid cells "
                 "(outlines, grey by certainty), their parts", fontsize=9)
    deg = np.arange(p.n) * 360 / p.n
    bx.plot(deg, whole, label="H^p, whole cells (main)", color="0.5")
    bx.plot(deg, p.primary, label="H^p, kept parts (branch)", color="k")
    bx.axhline(p.settings.threshold_high, color="#d62728", lw=0.8, ls="--", label="threshold_high")
    bx.axhline(p.settings.threshold_low, color="#2ca02c", lw=0.8, ls="--", label="threshold_low")
    k = (math.atan2(mid[1] - xy[1], mid[0] - xy[0]) % (2 * math.pi)) * 180 / math.pi
    bx.axvline(k, color="#2ca02c", lw=0.8, label="toward the gap")
    bx.set_xlabel("sector direction, deg (world)")
    bx.set_ylim(0, max(4 * p.settings.threshold_high, 1))
    bx.legend(fontsize=7)
    bx.set_title("primary polar histogram at that cycle", fontsize=9)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    kk = round(k / 5) % p.n
    print(f"cycle {i} t={replay.t[i]:.1f} s at ({xy[0]:.2f}, {xy[1]:.2f}); toward the gap ({k:.0f} deg): "
          f"whole cells {whole[kk]:.0f}, kept parts {p.primary[kk]:.0f}")


if __name__ == "__main__":
    main()
