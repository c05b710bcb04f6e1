"""Checking a velocity command against the map and the sonars before it is driven.

A path follower (pure pursuit) steers toward a point ahead on the path; on its way the
robot's circular footprint may sweep over a corner the path only grazes, and a differential
drive pressed on a corner spins its wheels while odometry drives on. :func:`guard` rolls the
command out over a short horizon (constant ``v``, ``omega``) and accepts it only when the
footprint keeps its clearance from occupied cells along the whole rollout, or, when the robot
is already closer than that (a sonar arc drawn over it), when the clearance never shrinks.
Otherwise it tries the same curvature slower, then turning on the spot toward the path (a
circular robot turning in place sweeps nothing new). It also never drives toward a sonar echo
inside the footprint's corridor, and slows down near obstacles.

Clearance comes from the planner as a callable ``clearance(xy (N, 2) m) -> (N,) m``: distance
from each point to the nearest occupied cell centre (capped; 0 outside the map). Units: m, s, rad.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from nav_bench.interface import Command, Observation, wrap_angle
from nav_bench.planners.follow import echo_mask, limit, robot_frame_hits

Clearance = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class GuardSettings:
    """How :func:`guard` checks a command.

    Attributes:
        required: clearance (m, robot centre to the nearest occupied cell centre) the rollout
            must keep; the robot radius plus half a cell, so the cell's edge stays outside.
        horizon: rollout length, s. steps: points checked along it.
        slow_distance: the speed falls linearly to 40 % as the clearance ahead drops from
            ``required + slow_distance`` to ``required``, m.
    """

    required: float
    horizon: float = 1.0
    steps: int = 6
    slow_distance: float = 0.2


def rollout(pose: np.ndarray, v: float, omega: float, horizon: float, steps: int) -> np.ndarray:
    """(steps, 2) positions, m, of a unicycle driving (v m/s, omega rad/s) from ``pose``
    (x, y, yaw) for ``horizon`` s, at ``horizon / steps`` intervals (the start excluded)."""
    t = np.linspace(horizon / steps, horizon, steps)
    x, y, yaw = (float(p) for p in pose[:3])
    if abs(omega) < 1e-6:
        return np.stack([x + v * t * math.cos(yaw), y + v * t * math.sin(yaw)], axis=1)
    r = v / omega
    th = yaw + omega * t
    return np.stack([x + r * (np.sin(th) - math.sin(yaw)), y - r * (np.cos(th) - math.cos(yaw))], axis=1)


def echo_blocks(obs: Observation, v: float, horizon: float) -> bool:
    """Is there a sonar echo in the corridor the footprint sweeps driving ``v`` m/s straight
    for ``horizon`` s (plus 5 cm), on the side it drives to (ahead for v > 0, behind for v < 0)?"""
    if v == 0.0:
        return False
    p = robot_frame_hits(obs)[echo_mask(obs)]
    if len(p) == 0:
        return False
    along = p[:, 0] * math.copysign(1.0, v)
    reach = obs.robot.radius + abs(v) * horizon + 0.05
    return bool(np.any((along > 0.0) & (along < reach) & (np.abs(p[:, 1]) < obs.robot.radius + 0.02)))


def is_safe(clear_now: float, clear_along: np.ndarray, required: float) -> bool:
    """A rollout keeps ``required`` m of clearance, or, if the robot is already closer than that,
    never gets closer than it is now (1 cm tolerance)."""
    floor = min(required, clear_now) - 0.01
    return bool(np.all(clear_along >= floor))


@dataclass(frozen=True)
class Guarded:
    """The command to drive and whether the wanted one had to be changed (``blocked``: not
    even a slower version of it was safe)."""

    command: Command
    blocked: bool


def guard(obs: Observation, wanted: Command, toward: float, clearance: Clearance,
          settings: GuardSettings) -> Guarded:
    """``wanted`` if its rollout is safe (slowed near obstacles); else a turn on the spot
    toward the world heading ``toward`` (rad) when the robot is more than 0.3 rad off it (the
    unsafe arc came from driving while turning); else the same curvature at 1/2 or 1/4 speed;
    else a turn on the spot (``blocked``).

    Never returns a command whose rollout brings the footprint closer to an occupied cell
    than allowed, nor one driving at an echo inside the footprint's corridor."""
    pose = np.asarray(obs.pose, dtype=float)
    clear_now = float(clearance(pose[None, :2])[0])
    err = wrap_angle(toward - float(pose[2]))
    turn = limit(0.0, 2.5 * err, obs.robot)
    if wanted.v == 0.0:
        return Guarded(wanted, False)
    kappa = wanted.omega / wanted.v
    for i, scale in enumerate((1.0, 0.5, 0.25)):
        v = wanted.v * scale
        along = clearance(rollout(pose, v, v * kappa, settings.horizon, settings.steps))
        if is_safe(clear_now, along, settings.required) and not echo_blocks(obs, v, settings.horizon):
            slow = (float(along.min()) - settings.required) / max(settings.slow_distance, 1e-6)
            v *= min(1.0, max(0.4, slow)) if v > 0 else 1.0
            return Guarded(limit(v, v * kappa, obs.robot), i > 0)
        if i == 0 and abs(err) > 0.3:
            return Guarded(turn, False)
    return Guarded(turn, True)
