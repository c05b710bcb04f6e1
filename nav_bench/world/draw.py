"""Top-down drawing of a world's true map on a matplotlib Axes (metres, equal aspect)."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import PatchCollection
from matplotlib.patches import Circle, Patch, Polygon

from nav_bench.specs import WorldSpec
from nav_bench.world.geometry import box_corners, static_geometry

OBSTACLE_COLOR = "#3b3b3b"
MOVER_COLOR = "#7b3fa0"


def obstacle_patches(world: WorldSpec) -> list[Patch]:
    """Matplotlib patches of the world's static obstacles (boxes as polygons, cylinders as circles)."""
    geometry = static_geometry(world)
    patches: list[Patch] = [Polygon(c, closed=True) for c in box_corners(geometry.boxes)]
    return patches + [Circle((cx, cy), r) for cx, cy, r in geometry.cylinders]


def draw_world(ax: Axes, world: WorldSpec, *, faint: bool = False, show_start_goal: bool = True,
               show_movers: bool = True, **_: Any) -> None:
    """Draw obstacles (and mover paths, start, goal) of ``world`` on ``ax``.

    ``faint`` draws the map light, as a backdrop for trajectories and planner grids.
    """
    alpha = 0.25 if faint else 1.0
    ax.add_collection(PatchCollection(obstacle_patches(world), facecolor=OBSTACLE_COLOR, edgecolor="none",
                                      alpha=alpha, zorder=1))
    if show_movers:
        for mover in world.movers:
            path = np.asarray(mover.path + ([mover.path[0]] if mover.mode == "loop" else []))
            ax.plot(path[:, 0], path[:, 1], ls=":", color=MOVER_COLOR, alpha=0.8, lw=1, zorder=2)
            radius = (mover.shape.cylinder.radius if mover.shape.cylinder
                      else max(mover.shape.box.size) / 2)
            ax.add_patch(Circle(mover.path[0], radius, facecolor=MOVER_COLOR, alpha=0.35 * alpha + 0.2,
                                edgecolor="none", zorder=2))
    if show_start_goal:
        x, y, yaw = world.start_pose
        ax.plot([x], [y], marker="o", ms=8, color="#1f77b4", zorder=5, label="start")
        ax.annotate("", xy=(x + 0.5 * np.cos(yaw), y + 0.5 * np.sin(yaw)), xytext=(x, y),
                    arrowprops={"arrowstyle": "->", "color": "#1f77b4"}, zorder=5)
        ax.plot([world.goal[0]], [world.goal[1]], marker="*", ms=14, color="#d62728", zorder=5,
                label="goal")
    sx, sy = world.size
    pad = 0.2
    ax.set_xlim(-pad, sx + pad)
    ax.set_ylim(-pad, sy + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")


def save_world_png(world: WorldSpec, path: str, *, title: str | None = None) -> None:
    """``nav-bench show``: the world from above as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sx, sy = world.size
    scale = 7.0 / max(sx, sy)
    fig, ax = plt.subplots(figsize=(max(3.0, sx * scale) + 1.0, max(3.0, sy * scale) + 0.6))
    draw_world(ax, world)
    ax.set_title(title or world.name)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
