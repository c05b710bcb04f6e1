"""Collisions: contact episodes of the robot with anything but the floor, and when to look.

Reading Bullet's contact points costs ~2 us a physics step, a tenth of the step itself, yet
most of an episode the robot is far from everything. :class:`ContactWindow` bounds how soon a
contact could begin: the robot's clearance from the true geometry (static obstacles exactly,
movers by their bounding discs), divided by the fastest the gap can close. Until then the
simulation skips the checks; the count is the same as checking every step.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from nav_bench.specs import Mover
from nav_bench.world.geometry import PointClearance, StaticGeometry, mover_radius

# A manifold point counts as touching when its separation is below this (m). PyBullet keeps
# contact points up to a few mm apart in its manifolds; those are near misses, not contacts.
CONTACT_DISTANCE = 1e-3
# m: gap kept in hand when bounding the time to the next contact (the collision shapes are the
# geometry's own boxes and cylinders, so this only covers rounding and Bullet's margins)
CLEARANCE_MARGIN = 0.02
# the robot's speed bound is its wheel-speed limit times this: a velocity motor can overshoot
# its target for a step or two, and nothing else pushes a robot that touches nothing
SPEED_SAFETY = 1.25


class ContactEpisodes:
    """Counts contact episodes: touching a body after at least one step apart from it counts once.

    Staying pressed against a wall is one episode; backing off and hitting it again is two.
    One compound scene body holds many obstacles, so sliding from one into a touching
    neighbour of the same body continues the episode.
    """

    def __init__(self) -> None:
        self.count = 0
        self.touching: frozenset[int] = frozenset()

    def update(self, touching: Iterable[int]) -> int:
        """Record the bodies touched in this physics step; returns the episodes that began."""
        now = frozenset(touching)
        new = len(now - self.touching)
        self.count += new
        self.touching = now
        return new


class ContactWindow:
    """How long the robot surely touches nothing, from its clearance now.

    A robot at clearance ``c`` from everything cannot touch anything before the gap closes:
    not within ``(c - margin) / (v_robot + v_mover)`` seconds, where ``v_robot`` bounds the
    speed of the robot's frame origin (wheel-speed limit; a turn on the spot moves the origin
    too when it is off the wheel axle, bounded through the footprint radius) and ``v_mover``
    is the fastest mover's speed.

    Args:
        geometry: the world's static obstacles.
        movers: the world's movers (their bounding discs count).
        robot_radius: footprint radius about the robot's frame origin, m.
        wheel_speed: fastest wheel rim speed, m/s (wheel radius x wheel-speed limit).
        wheel_base: distance between the wheels, m.
    """

    def __init__(self, geometry: StaticGeometry, movers: list[Mover], robot_radius: float,
                 wheel_speed: float, wheel_base: float) -> None:
        self.geometry = geometry
        self._static = PointClearance(geometry)  # per-cycle queries: footprint_clearance's arithmetic, cheaper
        self.robot_radius = float(robot_radius)
        self.mover_radii = [mover_radius(m) for m in movers]  # m: a few, read as Python floats
        # a point at distance d from the axle's midpoint moves at most v + |omega| d, with
        # |v| <= wheel_speed and |omega| <= 2 wheel_speed / wheel_base; d <= the footprint radius
        robot_speed = SPEED_SAFETY * wheel_speed * (1.0 + 2.0 * self.robot_radius / wheel_base)
        self.closing_speed = robot_speed + max((float(m.speed) for m in movers), default=0.0)

    def clearance(self, xy: np.ndarray, mover_xy: np.ndarray) -> float:
        """Gap (m) between the robot's footprint at ``xy`` (2,) and the nearest obstacle;
        ``mover_xy`` (M, 2) are the movers' positions now."""
        x, y = float(xy[0]), float(xy[1])
        gap = self._static(x, y)
        for (mx, my), radius in zip(np.asarray(mover_xy, dtype=float).tolist(), self.mover_radii,
                                    strict=True):  # a few movers: Python floats beat NumPy calls
            gap = min(gap, math.hypot(mx - x, my - y) - radius)
        return gap - self.robot_radius

    def free_for(self, xy: np.ndarray, mover_xy: np.ndarray) -> float:
        """Seconds during which the robot at ``xy`` surely touches nothing (0: check now)."""
        return max(0.0, (self.clearance(xy, mover_xy) - CLEARANCE_MARGIN) / self.closing_speed)
