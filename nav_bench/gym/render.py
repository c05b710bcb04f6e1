"""A top-down frame of an episode: the world, the trajectory, the robot and its sonar cones."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from nav_bench.interface import RobotInfo
from nav_bench.specs import WorldSpec

SONAR_COLOR = "#1f9bd1"
TRAIL_COLOR = "#d62728"


def draw_frame(figure: Any, world: WorldSpec, robot: RobotInfo, pose: np.ndarray,
               ranges: np.ndarray, trail: Sequence[tuple[float, float]], *, px: int = 480,
               show: bool = False) -> tuple[np.ndarray, Any]:
    """An (H, W, 3) uint8 frame; ``figure`` is reused from call to call (None at first)."""
    from matplotlib.patches import Circle, Wedge

    from nav_bench.world.draw import draw_world

    if figure is None:
        if show:
            import matplotlib.pyplot as plt

            figure = plt.figure(figsize=(px / 100, px / 100), dpi=100)
        else:
            from matplotlib.backends.backend_agg import FigureCanvasAgg
            from matplotlib.figure import Figure

            figure = Figure(figsize=(px / 100, px / 100), dpi=100)
            FigureCanvasAgg(figure)
    figure.clf()
    ax = figure.add_axes((0.01, 0.01, 0.98, 0.98))
    draw_world(ax, world)
    ax.set_axis_off()
    x, y, yaw = (float(v) for v in pose)
    sonar = robot.sonar
    c, s = math.cos(yaw), math.sin(yaw)
    for angle, offset, r in zip(sonar.angles, sonar.offsets, ranges, strict=True):
        ox, oy = x + c * offset[0] - s * offset[1], y + s * offset[0] + c * offset[1]
        mid = math.degrees(yaw + angle)
        half = math.degrees(sonar.cone) / 2
        echo = r < sonar.max_range - 1e-6
        ax.add_patch(Wedge((ox, oy), float(r), mid - half, mid + half, facecolor=SONAR_COLOR,
                           alpha=0.35 if echo else 0.12, edgecolor="none", zorder=3))
    if len(trail) > 1:
        xy = np.asarray(trail)
        ax.plot(xy[:, 0], xy[:, 1], color=TRAIL_COLOR, lw=1.5, zorder=4)
    ax.add_patch(Circle((x, y), robot.radius, facecolor="#ffbf00", edgecolor="black", lw=1,
                        zorder=6))
    ax.plot([x, x + robot.radius * c], [y, y + robot.radius * s], color="black", lw=1.5, zorder=7)
    figure.canvas.draw()
    frame = np.asarray(figure.canvas.buffer_rgba())[:, :, :3].copy()
    if show:
        import matplotlib.pyplot as plt

        plt.pause(0.001)
    return frame, figure
