"""Noticing that the robot makes no progress, and the recovery users know from ROS navigation.

:class:`ProgressWatch` decides from what a planner sees (odometry and sonar ranges) whether
the robot has made progress: it got ``progress_m`` farther from where it last made progress,
or ``progress_m`` closer to the goal than ever before, or it crept a third of that in a
straight line over at least ``pinned_s`` (odometry travel at most 1.5 times the displacement:
a robot squeezing through a gap at a few cm/s is getting somewhere; one rocking to and fro is
not). Odometry alone is not enough: a robot
pressed on a corner spins its wheels and its odometry drives on. So a cycle counts as *pinned*
when, over the last ``pinned_s``, odometry moved the robot but the sonar ranges did not change
as that motion predicts (each echoing sonar should see its range change by the displacement's
component along its axis); odometry moves made while pinned are not progress.

:class:`Recovery` is the sequence of ROS move_base's recovery behaviours reduced to what six
sonars allow: back up ``backup_m`` (stopping early when a rear sonar sees something within
10 cm of the body or, given the planner's map clearance, when the next 10 cm backward would
bring the body nearer an occupied cell than allowed: the default robot has no rear sonars), rotate in place ``rotate_rad`` to re-sense the surroundings, then hand back
to the planner, which re-plans from scratch (and, when it still has no path, may clear its map
like ROS's clear_costmap recovery). Units: m, s, rad.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from enum import Enum

import numpy as np

from nav_bench.interface import Command, Observation, StuckReason
from nav_bench.planners.follow import echo_mask, limit
from nav_bench.planners.footprint import Clearance, is_safe, pose_floats, rollout

CREEP_SHARE = 1.0 / 3.0  # of progress_m: a straight creep this long counts as progress
CREEP_TRAVEL = 1.5  # odometry travel over displacement below which a creep is straight
PINNED_CONE = math.radians(30.0)  # sonars within this of the direction of motion judge pinning
BACKUP_CHECK_M = 0.1  # m: the back-up looks this far behind the robot on the map


def _goal(obs: Observation) -> tuple[float, float]:
    """The goal (x, y), m, as Python floats (the same values)."""
    gx, gy = np.asarray(obs.goal, dtype=float)[:2].tolist()
    return gx, gy


class RecoveryPhase(str, Enum):
    """A step of the recovery (the ``phase`` of a ``recovery`` event)."""

    BACKUP = "backup"
    ROTATE = "rotate"
    CLEAR_MAP = "clear_map"
    REPLAN = "replan"

    def __str__(self) -> str:
        return self.value


@dataclass(frozen=True)
class RecoverySettings:
    """Attributes:
        after_s: seconds without progress before a recovery starts.
        progress_m: displacement (or gain toward the goal) that counts as progress, m.
        pinned_s: window over which odometry and sonar motion are compared, s.
        backup_m: how far to back up, m. backup_speed: m/s.
        rotate_rad: how far to turn in place to re-sense, rad. omega: turn rate, rad/s.
    """

    after_s: float = 6.0
    progress_m: float = 0.3
    pinned_s: float = 1.5
    backup_m: float = 0.25
    backup_speed: float = 0.12
    rotate_rad: float = 2 * math.pi
    omega: float = 1.0


class ProgressWatch:
    """Time since the robot last made progress, and why not (pinned, oscillating).

    Positions are kept as Python floats (m, rad): the bookkeeping of six sonars and one pose a
    cycle costs less so than as small arrays, and the values are the same (a float64
    subtraction is the same IEEE operation either way; distances still come from ``np.hypot``
    and the sonar geometry from NumPy's ``cos``/``sin``, which a Python ``math`` function may
    round differently in the last bit)."""

    def __init__(self, settings: RecoverySettings) -> None:
        self.s = settings
        self.anchor = (0.0, 0.0)  # (x, y) where the robot last made progress, m
        self.t_progress = 0.0
        self.best_goal = math.inf
        self.travel = 0.0  # odometry path length since the last progress, m
        self.pinned = False
        # (t, (x, y, yaw), ranges with NaN where no echo) over the last pinned_s
        self._history: deque[tuple[float, tuple[float, float, float], np.ndarray]] = deque()
        self._last_xy: tuple[float, float] | None = None

    def restart(self, obs: Observation) -> None:
        """Count from now (after a recovery, or at the start of an episode)."""
        x, y, _ = pose_floats(obs.pose)
        gx, gy = _goal(obs)
        self.anchor, self.t_progress, self.travel = (x, y), obs.t, 0.0
        self.best_goal = float(np.hypot(gx - x, gy - y))
        self._history.clear()
        self._last_xy = (x, y)
        self.pinned = False

    def update(self, obs: Observation) -> None:
        pose = pose_floats(obs.pose)
        x, y, _ = pose
        if self._last_xy is None:
            self.restart(obs)
        lx, ly = self._last_xy
        self.travel += float(np.hypot(x - lx, y - ly))
        self._last_xy = (x, y)
        ranges = np.where(echo_mask(obs), np.asarray(obs.ranges, dtype=float), np.nan)
        self._history.append((obs.t, pose, ranges))
        while self._history and self._history[0][0] < obs.t - self.s.pinned_s:
            self._history.popleft()
        self.pinned = self._pinned(obs)
        if self.pinned:
            return
        gx, gy = _goal(obs)
        to_goal = float(np.hypot(gx - x, gy - y))
        moved = float(np.hypot(x - self.anchor[0], y - self.anchor[1]))
        crept = (moved >= CREEP_SHARE * self.s.progress_m and self.travel <= CREEP_TRAVEL * moved
                 and obs.t - self.t_progress >= self.s.pinned_s)  # slow: the pinned test has had its window
        if moved >= self.s.progress_m or to_goal <= self.best_goal - self.s.progress_m or crept:
            self.anchor, self.t_progress, self.travel = (x, y), obs.t, 0.0
            self.best_goal = min(self.best_goal, to_goal)

    def _pinned(self, obs: Observation) -> bool:
        """Odometry moved >= 8 cm in the window, but the echoing sonars looking within
        ``PINNED_CONE`` of the direction of motion saw their ranges change by less than 30 % of
        what that displacement predicts along their axes."""
        t0, (x0, y0, yaw0), r0 = self._history[0]
        if obs.t - t0 < 0.5 * self.s.pinned_s:
            return False
        (x1, y1, _), r1 = self._history[-1][1], self._history[-1][2]
        sx, sy = x1 - x0, y1 - y0  # the shift, m
        if float(np.hypot(sx, sy)) < 0.08:
            return False
        sonar = obs.robot.sonar
        axes = yaw0 + sonar.angles
        predicted = -(sx * np.cos(axes) + sy * np.sin(axes))  # range change, m
        # only sonars looking along the motion: the range of one looking sideways at a wall the
        # robot drives along does not change however far it drives (a 45 deg sonar in a long
        # corridor called a robot cruising along a wall pinned, in the generated mazes)
        along = np.abs(np.angle(np.exp(1j * (axes - math.atan2(sy, sx))))) <= PINNED_CONE
        seen = np.isfinite(r0) & np.isfinite(r1) & (np.abs(predicted) > 0.04) & along
        if not seen.any():
            return False
        return bool(np.abs(r1[seen] - r0[seen]).sum() < 0.3 * np.abs(predicted[seen]).sum())

    def stalled_for(self, t: float) -> float:
        """Seconds since the last progress."""
        return t - self.t_progress

    def reason(self) -> StuckReason | None:
        """PINNED while the sonars contradict odometry, OSCILLATING when the robot travelled
        more than four times ``progress_m`` without getting that far from where it was."""
        if self.pinned:
            return StuckReason.PINNED
        if self.travel > 4 * self.s.progress_m:
            return StuckReason.OSCILLATING
        return None


class Recovery:
    """Back up, rotate in place, then report done (the caller re-plans). One at a time."""

    def __init__(self, settings: RecoverySettings) -> None:
        self.s = settings
        self.phase: RecoveryPhase | None = None
        self.count = 0
        self._start = np.zeros(3)
        self._t0 = 0.0
        self._turned = 0.0
        self._last_yaw = 0.0

    @property
    def active(self) -> bool:
        return self.phase is not None

    def start(self, obs: Observation, backup: bool = True) -> None:
        """Begin: back up first (``backup``; not when the planner only lost its path), then rotate."""
        self.count += 1
        self._enter(RecoveryPhase.BACKUP if backup else RecoveryPhase.ROTATE, obs)

    def _enter(self, phase: RecoveryPhase, obs: Observation) -> None:
        self.phase = phase
        self._start = np.asarray(obs.pose, dtype=float).copy()
        self._t0 = obs.t
        self._turned = 0.0
        self._last_yaw = float(obs.pose[2])

    def _rear_blocked(self, obs: Observation) -> bool:
        """A rear-facing sonar (axis more than 100 deg off the heading) echoes within 10 cm of
        the body (ranges are measured from the mounts on the body's rim)."""
        s = obs.robot.sonar
        rear = np.abs(np.angle(np.exp(1j * s.angles))) > math.radians(100)
        close = echo_mask(obs) & (np.asarray(obs.ranges) < 0.1)
        return bool(np.any(rear & close))

    def _map_blocks_backup(self, obs: Observation, clearance: Clearance | None, required: float) -> bool:
        """Would the next ``BACKUP_CHECK_M`` backward bring the footprint nearer an occupied cell
        of the map than ``required`` (or, already nearer, nearer still)?"""
        if clearance is None:
            return False
        pose = np.asarray(obs.pose, dtype=float)
        now = float(clearance(pose[None, :2])[0])
        steps = max(2, math.ceil(BACKUP_CHECK_M / 0.02))
        along = clearance(rollout(pose, -BACKUP_CHECK_M, 0.0, 1.0, steps))
        return not is_safe(now, along, required)

    def step(self, obs: Observation, clearance: Clearance | None = None,
             required: float = 0.0) -> Command | None:
        """This cycle's command; None when the recovery has finished (the caller re-plans).
        ``clearance`` (m from points to the map's occupied cells) and ``required`` (m) let the
        back-up stop before the map's obstacles behind the robot."""
        s = self.s
        if self.phase is RecoveryPhase.BACKUP:
            moved = float(np.hypot(*(np.asarray(obs.pose[:2]) - self._start[:2])))
            timed_out = obs.t - self._t0 > 2.0 * s.backup_m / max(s.backup_speed, 1e-3) + 1.0
            if (moved >= s.backup_m or timed_out or self._rear_blocked(obs)
                    or self._map_blocks_backup(obs, clearance, required)):
                self._enter(RecoveryPhase.ROTATE, obs)
            else:
                return limit(-s.backup_speed, 0.0, obs.robot)
        if self.phase is RecoveryPhase.ROTATE:
            yaw = float(obs.pose[2])
            self._turned += abs(math.remainder(yaw - self._last_yaw, 2 * math.pi))
            self._last_yaw = yaw
            timed_out = obs.t - self._t0 > 2.0 * s.rotate_rad / max(s.omega, 1e-3) + 1.0
            if self._turned < s.rotate_rad and not timed_out:
                return limit(0.0, s.omega, obs.robot)
        self.phase = None
        return None
