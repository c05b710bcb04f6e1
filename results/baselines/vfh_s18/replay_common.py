"""Shared by contact_window.py and heading_diff.py: frames between odometry and truth, the
body's touching point, and a log of which cycle last carved each part of a replayed planner's
carving and whether the body did (the part lay within the radius of that cycle's pose)."""
import math

import numpy as np

from nav_bench.planners.footprint import cell_parts
from nav_bench.world.geometry import clearance

RADIUS = 0.18  # m, the diffbot's body


def rotate_about(points, a_from, a_to, angle):
    """(K, 2) points moved so that ``a_from`` (2,) goes to ``a_to`` (2,), turned by ``angle`` rad."""
    c, s = math.cos(angle), math.sin(angle)
    d = np.atleast_2d(points) - a_from
    return np.stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]], 1) + a_to


def odom_to_true(points, odom, true):
    """(K, 2) odometry-frame points (m) in the world, by the transform of one cycle."""
    return rotate_about(points, odom[:2], true[:2], float(true[2] - odom[2]))


def true_to_odom(point, odom, true):
    """A world point (2,) in the odometry frame of one cycle."""
    return rotate_about(point, true[:2], odom[:2], float(odom[2] - true[2]))[0]


def touch_point(geometry, xy, yaw):
    """The body point nearest an obstacle (2,), m, and its bearing from the heading, deg."""
    ang = np.radians(np.arange(0, 360, 5))
    ring = xy + (RADIUS + 0.01) * np.stack([np.cos(yaw + ang), np.sin(yaw + ang)], 1)
    j = int(np.argmin(clearance(geometry, ring)))
    bearing = float(yaw + ang[j])
    return xy + RADIUS * np.array([math.cos(bearing), math.sin(bearing)]), (math.degrees(ang[j]) + 180) % 360 - 180


class CarveLog:
    """Per part of the carving's grid: the cycle that last carved it (-1: none) and whether the
    body did. Call :meth:`note` after each replayed ``act``."""

    def __init__(self, planner):
        self.planner = planner
        shape = planner.carving.carved_t.shape
        self.cycle = np.full(shape, -1, dtype=np.int32)
        self.body = np.zeros(shape, dtype=bool)

    def note(self, i, obs):
        carved_t, f = self.planner.carving.carved_t, self.planner.frame
        fresh = carved_t == np.float32(obs.t)  # (rows, cols, parts): carved this cycle
        cells = np.argwhere(fresh.any(axis=2))
        if len(cells) == 0:
            return
        centres = np.stack([f.xmin + (cells[:, 1] + 0.5) * f.cell, f.ymin + (cells[:, 0] + 0.5) * f.cell], 1)
        parts = cell_parts(centres, f.cell)
        under = np.hypot(parts[..., 0] - obs.pose[0], parts[..., 1] - obs.pose[1]) <= RADIUS
        mask = fresh[cells[:, 0], cells[:, 1]]  # (M, parts)
        rows, cols = cells[:, 0], cells[:, 1]
        self.cycle[rows, cols] = np.where(mask, i, self.cycle[rows, cols])
        self.body[rows, cols] = np.where(mask, under, self.body[rows, cols])
