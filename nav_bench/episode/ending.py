"""How an episode ends: one small object per end condition, checked in order every cycle.

Each ending is called with the simulated time (s) and the robot's true position (m) and says
whether the episode ends now; its ``outcome`` names the end. A new end condition is one more
class with ``outcome`` and ``__call__``; which endings an episode has, and their values, is its
protocol's choice (:meth:`nav_bench.episode.protocol.Protocol.endings`).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Sequence
from typing import Protocol

import numpy as np

from nav_bench.interface import Outcome, StuckReason


class Ending(Protocol):
    outcome: Outcome

    def __call__(self, t: float, xy: np.ndarray) -> bool: ...


class GoalReached:
    """The true position is within ``tolerance`` (m) of the goal."""

    outcome = Outcome.REACHED

    def __init__(self, goal: np.ndarray, tolerance: float) -> None:
        self.goal, self.tolerance = goal, tolerance
        self._gx, self._gy = float(goal[0]), float(goal[1])

    def __call__(self, t: float, xy: np.ndarray) -> bool:
        # scalars: np.hypot of the same differences, without a (2,) array per cycle
        return bool(np.hypot(float(xy[0]) - self._gx, float(xy[1]) - self._gy) < self.tolerance)


class TimeLimit:
    """The simulated time reached ``limit_s``."""

    outcome = Outcome.TIMEOUT

    def __init__(self, limit_s: float) -> None:
        self.limit_s = limit_s

    def __call__(self, t: float, xy: np.ndarray) -> bool:
        return t >= self.limit_s - 1e-9


class Stuck:
    """No progress: the robot stayed within ``radius`` (m) of one point for ``seconds``, or
    (an oscillating or circling robot) its true positions over the last
    ``AREA_WINDOW x seconds`` all fit in a disc of radius ``area_radius`` (m).

    The second rule is judged on the positions' bounding box: its half-diagonal <= ``area_radius``
    means a disc of that radius around the box's centre holds them all. Its window is longer
    than ``seconds`` because planners that escape by oscillating (EO/PC's chains, VFH+ and
    TangentBug in the labyrinth) stayed within 0.85 m for 90 s and still reached the goal in
    the stored studies; see :data:`DEFAULT_AREA_RADIUS`. ``fired`` names the rule that ended
    the episode (``"radius"`` or ``"area"``), None while it goes on.
    """

    outcome = Outcome.STUCK

    def __init__(self, seconds: float, radius: float, start_xy: np.ndarray,
                 area_radius: float | None = None) -> None:
        self.seconds, self.radius, self.area_radius = seconds, radius, area_radius
        self.anchor: tuple[float, float] = (float(start_xy[0]), float(start_xy[1]))  # m
        self.since = 0.0
        self.fired: str | None = None
        self._area = SlidingBox(AREA_WINDOW * seconds) if area_radius is not None else None

    def __call__(self, t: float, xy: np.ndarray) -> bool:
        if self._area is not None:
            half_diagonal = self._area.add(t, float(xy[0]), float(xy[1]))
            if half_diagonal is not None and half_diagonal <= self.area_radius:
                self.fired = "area"
                return True
        x, y = float(xy[0]), float(xy[1])
        if np.hypot(x - self.anchor[0], y - self.anchor[1]) > self.radius:
            self.anchor, self.since = (x, y), t
            return False
        if t - self.since >= self.seconds:
            self.fired = "radius"
            return True
        return False


# The area rule's window in multiples of ``stuck_s`` and its default radius (m), chosen on the
# traces of the stored studies (default suite, physics fidelity runs at 60 and 120 Hz, EO/PC
# convergence and long-wall sweeps with stuck_s = 120 s; 520 reached episodes, 109 timeouts):
# with a window of 3 x stuck_s and 0.6 m no reached episode would have ended earlier (the
# closest came to 0.85 m), and 26 of the 109 timeouts end stuck (9 of the default suite's 27:
# VFH+ rocking in the concave trap, TangentBug and VFH+ circling in the labyrinth and the
# very-complex world). A window of 1 x stuck_s cut reached episodes from 0.32 m on.
AREA_WINDOW = 3.0
DEFAULT_AREA_RADIUS = 0.6


class SlidingBox:
    """The bounding box of the positions of the last ``window_s`` seconds, updated in O(1)
    amortised time per sample (a monotonic deque per side: the running min/max of a window)."""

    def __init__(self, window_s: float) -> None:
        self.window_s = window_s
        self.t0: float | None = None
        # (t, value) pairs of the running minima of x, -x, y, -y
        self._sides: list[deque[tuple[float, float]]] = [deque() for _ in range(4)]

    def add(self, t: float, x: float, y: float) -> float | None:
        """Add the position at ``t``; the box's half-diagonal (m) once ``window_s`` of positions
        are held (None before)."""
        if self.t0 is None:
            self.t0 = t
        start = t - self.window_s - 1e-9
        for side, v in zip(self._sides, (x, -x, y, -y), strict=True):  # max x: -(min of -x)
            while side and side[-1][1] >= v:  # a newer, smaller value hides older larger ones
                side.pop()
            side.append((t, v))
            while side[0][0] < start:
                side.popleft()
        if t - self.t0 < self.window_s - 1e-9:
            return None
        (_, min_x), (_, neg_max_x), (_, min_y), (_, neg_max_y) = (s[0] for s in self._sides)
        return 0.5 * float(np.hypot(-neg_max_x - min_x, -neg_max_y - min_y))


class Collided:
    """The robot touched something: ``collisions()`` counts its distinct contacts so far."""

    outcome = Outcome.COLLISION

    def __init__(self, collisions: Callable[[], int]) -> None:
        self.collisions = collisions

    def __call__(self, t: float, xy: np.ndarray) -> bool:
        return self.collisions() > 0


# what counts as commanded motion and as achieved motion when a stuck episode is classified
STOPPED_V, STOPPED_OMEGA = 0.01, 0.05  # mean |v| (m/s) and |omega| (rad/s) commands below these
PINNED_SHARE = 0.25  # achieved under this share of the commanded distance (or turn): pinned
MIN_DRIVE_M, MIN_TURN_RAD = 0.3, 0.5  # commanded distance / turn over the window worth judging


def classify_stuck(t: np.ndarray, true_pose: np.ndarray, cmd: np.ndarray,
                   window_s: float) -> StuckReason:
    """Why a robot that ended ``stuck`` made no progress, from its last ``window_s`` seconds.

    Args:
        t: (T,) s. true_pose: (T, 3) x, y, yaw (m, m, rad). cmd: (T, 2) commanded v (m/s),
        omega (rad/s), the command of each cycle held until the next sample.
    Returns:
        STOPPED when the planner commanded (almost) nothing; PINNED when the wheels were
        driven but the body achieved under a quarter of the commanded distance (or, turning
        in place, of the commanded turn); OSCILLATING otherwise (it moved, inside a small area).
    """
    keep = t >= t[-1] - window_s - 1e-9
    t, pose, cmd = t[keep], true_pose[keep], cmd[keep]
    dt = np.diff(t)  # the command of sample i acts over [t_i, t_i+1]
    if len(dt) == 0:
        return StuckReason.STOPPED
    span = float(t[-1] - t[0])
    cmd_dist = float(np.abs(cmd[:-1, 0]) @ dt)
    cmd_turn = float(np.abs(cmd[:-1, 1]) @ dt)
    if cmd_dist < STOPPED_V * span and cmd_turn < STOPPED_OMEGA * span:
        return StuckReason.STOPPED
    dist = float(np.hypot(*np.diff(pose[:, :2], axis=0).T).sum())
    turn = float(np.abs(np.diff(np.unwrap(pose[:, 2]))).sum())
    if cmd_dist >= MIN_DRIVE_M and dist < PINNED_SHARE * cmd_dist:
        return StuckReason.PINNED
    if cmd_dist < MIN_DRIVE_M and cmd_turn >= MIN_TURN_RAD and turn < PINNED_SHARE * cmd_turn:
        return StuckReason.PINNED
    return StuckReason.OSCILLATING


def first_ending(checks: Sequence[Ending], t: float, xy: np.ndarray) -> Outcome | None:
    """The outcome of the first ending that holds, or None: the episode goes on."""
    for check in checks:
        if check(t, xy):
            return check.outcome
    return None
