"""The types every layer shares; imports nothing of nav-bench.

What a planner sees (:class:`Observation`) and returns (:class:`Command`), the robot's geometry
(:class:`RobotInfo`, :class:`SonarInfo`), what a planner reports (:class:`PlannerEvent`) and how
an episode ends (:class:`Outcome`). The simulator, the grid maps, the planners and the episode
all speak these. Units: metres, seconds, radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum
from typing import Any

import numpy as np


class Outcome(str, Enum):
    """How an episode ended (a result row's ``outcome``; the value is the stored word)."""

    REACHED = "reached"  # the robot's true position came within the goal tolerance
    TIMEOUT = "timeout"  # the simulated time limit passed
    STUCK = "stuck"  # the robot stayed within a small circle for too long
    COLLISION = "collision"  # the robot touched something under a protocol where that ends it (barn)
    ERROR = "error"  # the planner or the simulation failed; the row carries the traceback

    def __str__(self) -> str:
        return self.value


@dataclass(frozen=True)
class SonarInfo:
    """Where the sonars sit and what they can measure (fixed for an episode).

    Attributes:
        angles: (K,) mount yaw of each sonar relative to the robot heading, rad (CCW +).
        offsets: (K, 2) mount position of each sonar in the robot frame, m (x forward, y left).
        cone: full opening angle of each cone, rad.
        min_range, max_range: measurable range, m. A reading of ``max_range`` means "nothing seen".
    """

    angles: np.ndarray
    offsets: np.ndarray
    cone: float
    min_range: float
    max_range: float


@dataclass(frozen=True)
class RobotInfo:
    """Robot geometry and limits a planner may use.

    Attributes:
        radius: body radius, m. wheel_base: distance between the wheels, m.
        v_max: top translation speed the drive allows, m/s. omega_max: top turn rate, rad/s.
    """

    radius: float
    wheel_base: float
    v_max: float
    omega_max: float
    sonar: SonarInfo


@dataclass(frozen=True)
class Observation:
    """One control cycle's input to a planner.

    Attributes:
        t: simulated time since the start, s.
        pose: (3,) odometry pose estimate ``x, y, yaw`` (m, m, rad) in the world frame.
        goal: (2,) goal position, m.
        ranges: (K,) sonar readings, m, in ``robot.sonar`` order; ``max_range`` = no echo.
        robot: geometry and limits.
        bounds: ``(xmin, ymin, xmax, ymax)`` of the area the grids should cover, m
            (the world's extent; the paper sizes its fixed grid map from it).
        dt: control period, s.
    """

    t: float
    pose: np.ndarray
    goal: np.ndarray
    ranges: np.ndarray
    robot: RobotInfo
    bounds: tuple[float, float, float, float]
    dt: float

    def sonar_hits(self) -> np.ndarray:
        """(K, 2) world-frame points of the readings (max-range readings included), m."""
        x, y, yaw = self.pose
        s = self.robot.sonar
        c, si = math.cos(yaw), math.sin(yaw)
        ox = x + c * s.offsets[:, 0] - si * s.offsets[:, 1]
        oy = y + si * s.offsets[:, 0] + c * s.offsets[:, 1]
        ang = yaw + s.angles
        return np.stack([ox + self.ranges * np.cos(ang), oy + self.ranges * np.sin(ang)], axis=1)


@dataclass(frozen=True)
class Command:
    """Body velocity command: translation ``v`` (m/s, + forward) and turn rate ``omega`` (rad/s, CCW +)."""

    v: float
    omega: float


@dataclass(frozen=True)
class PlannerEvent:
    """Something a planner wants recorded in the trace (a re-plan, a blocked cycle...).

    ``kind`` is a short word; ``replan`` events are counted in the result row's ``replans``.
    ``data`` holds plain JSON-able values (lists, floats, strings).
    """

    kind: str
    t: float
    data: dict[str, Any] = field(default_factory=dict)


def wrap_angle(a: float) -> float:
    """Angle wrapped to (-pi, pi]."""
    a = (a + math.pi) % (2 * math.pi) - math.pi
    return math.pi if a == -math.pi else a
