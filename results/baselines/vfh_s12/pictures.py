"""The pictures of results/baselines/vfh_s12/README.md, from episode traces (`nav-bench episode
... --trace`). PYTHONPATH=$PWD python results/baselines/vfh_s12/pictures.py TRACE_DIR OUT_DIR

* local_minimum.png: maze_16 and office_7 (main's VFH+): the whole trajectory (faint), the last
  90 s (bold), and the shortest way on from the loop's point nearest the goal (dashed).
* gap_office_11.png: office_11 near the goal: left, the final sonar map (main's VFH+) with the
  true obstacles outlined, the last 90 s and the shortest way on (the 0.61 m gap NE of the big
  cylinder); right, the same VFH+ reading the true map (TRACE_DIR/office_11_oracle.npz,
  oracle.py) passes the 0.64 m gap SE of it.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PatchCollection

from nav_bench.world.draw import draw_world, obstacle_patches
from nav_bench.world.geometry import static_geometry
from nav_bench.world.load import world_from_data
from nav_bench.world.optimal import raster_optimal_path
from nav_bench.world.raster import rasterize


def load(path: Path):
    tr = np.load(path, allow_pickle=True)
    meta = json.loads(str(tr["meta"]))
    return tr, meta, world_from_data(meta["world"])


def way_on(world, xy):
    """Shortest path (robot radius 0.18 m) from ``xy`` to the goal, (K, 2) m."""
    raster = rasterize(static_geometry(world), 0.05, inflate=0.18)
    return np.asarray(raster_optimal_path(raster, tuple(xy), tuple(world.goal), snap=0.45).points)


def loop_best(tr, goal):
    """The point of the last 90 s nearest the goal, m."""
    t, xy = tr["t"], tr["true_pose"][:, :2]
    loop = xy[t >= t[-1] - 90]
    return loop[int(np.argmin(np.hypot(*(loop - goal).T)))]


def panel(ax, tr, meta, world, title):
    draw_world(ax, world)
    t, xy = tr["t"], tr["true_pose"][:, :2]
    last = t >= t[-1] - 90
    ax.plot(xy[:, 0], xy[:, 1], color="#1f77b4", alpha=0.3, lw=1, label="trajectory")
    ax.plot(xy[last, 0], xy[last, 1], color="#1f77b4", lw=2, label="last 90 s")
    best = loop_best(tr, np.asarray(world.goal))
    path = way_on(world, best)
    ax.plot(path[:, 0], path[:, 1], "--", color="#2ca02c", lw=1.5, label="shortest way on")
    ax.plot(*xy[-1], "s", color="k", ms=5, label="end")
    ax.set_title(title, fontsize=9)


def local_minimum(trace_dir: Path, out: Path) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.2), gridspec_kw={"width_ratios": [1, 1.45]})
    for ax, name, text in ((axes[0], "maze_16", "maze_16: timeout 261 s; the way on (SW) first climbs 3.9 m"),
                           (axes[1], "office_7", "office_7: timeout 289.5 s; goal behind the wall y = 3.55, "
                                                 "the way on (back west) climbs 2.4 m")):
        tr, meta, world = load(trace_dir / f"{name}.npz")
        panel(ax, tr, meta, world, text)
    axes[1].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    fig.suptitle("VFH+ (main) local minima: the way on first leads away from the goal", fontsize=10)
    fig.savefig(out / "local_minimum.png", dpi=90, bbox_inches="tight")
    plt.close(fig)


def map_panel(ax, tr, world, box, title, sonar: bool):
    x0, x1, y0, y1 = box
    if sonar:
        pmo = tr["state__pmo"].astype(float)
        ax.imshow(pmo, origin="lower", extent=(0, pmo.shape[1] * 0.1, 0, pmo.shape[0] * 0.1),
                  cmap="gray_r", vmin=0, vmax=100, zorder=0)
    ax.add_collection(PatchCollection(obstacle_patches(world), facecolor="none", edgecolor="#d62728",
                                      lw=1.2, zorder=3))
    t, xy = tr["t"], tr["true_pose"][:, :2]
    last = t >= t[-1] - 90
    ax.plot(xy[:, 0], xy[:, 1], color="#1f77b4", alpha=0.35, lw=1)
    ax.plot(xy[last if sonar else slice(None), 0], xy[last if sonar else slice(None), 1],
            color="#1f77b4", lw=2)
    if sonar:
        path = way_on(world, loop_best(tr, np.asarray(world.goal)))
        ax.plot(path[:, 0], path[:, 1], "--", color="#2ca02c", lw=1.5)
    ax.plot(*world.goal, marker="*", ms=14, color="#d62728")
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")


def gap(trace_dir: Path, out: Path) -> None:
    tr, _meta, world = load(trace_dir / "office_11.npz")
    oracle, _, _ = load(trace_dir / "office_11_oracle.npz")
    box = (8.3, 11.8, 4.0, 7.1)
    fig, axes = plt.subplots(1, 2, figsize=(11, 5))
    map_panel(axes[0], tr, world, box, "office_11, main's sonar map at 289.5 s (black = certain), true obstacles red;\n"
              "last 90 s blue; shortest way on green (0.61 m gap NE of the big cylinder)", sonar=True)
    map_panel(axes[1], oracle, world, box, "the same VFH+ reading the true map (0.1 m raster): reached in 54.0 s\n"
              "through the 0.64 m gap SE of the big cylinder", sonar=False)
    fig.savefig(out / "gap_office_11.png", dpi=90, bbox_inches="tight")
    plt.close(fig)


if __name__ == "__main__":
    trace_dir, out = Path(sys.argv[1]), Path(sys.argv[2])
    local_minimum(trace_dir, out)
    gap(trace_dir, out)
