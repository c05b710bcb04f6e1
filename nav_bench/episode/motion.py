"""Motion metrics: pure functions from an episode's trace arrays to how the robot moved.

Every function reads plain arrays (times ``t`` (T,) s, true poses (T, 3) x, y, yaw in m, m,
rad, per-cycle clearances and planning times) and returns plain numbers; the result row calls
:func:`motion_metrics` once. Velocities are finite differences of the true poses at the
control rate (10 Hz by default), so they are what the robot did, not what the planner asked.

Definitions (and where they come from):

* **Linear velocity** ``v_k``: the displacement of interval ``k`` projected on the mean heading
  of the interval, over its duration (signed: reversing is negative). **Angular velocity**
  ``omega_k``: the wrapped heading change over the duration.
* **Linear acceleration** ``a = dv/dt`` (differences of ``v`` at interval midpoints);
  ``accel_mean_mps2`` is the mean of ``|a|`` over the samples, ``accel_max_mps2`` its
  maximum. Mean and peak acceleration are smoothness measures of MRPB (Wen et al., "MRPB 1.0",
  ICRA 2021) and Arena-Rosnav (Kästner et al., IROS 2022), and asked for in nav2 #3239.
* **Integrated jerk**: ``jerk_linear = sum j^2 dt`` with ``j = da/dt`` (m^2/s^5) and
  ``jerk_angular`` the same for the angular jerk ``d^2 omega / dt^2`` (rad^2/s^5): the
  integral of squared jerk of the minimum-jerk model (Flash & Hogan, J. Neuroscience 5(7),
  1985), the smoothness term of Bench-MR (Heiden et al., RA-L 2021) and MRPB.
* **Angle over length** ``curvature_per_m``: the sum of the absolute turning angles between
  consecutive path segments (segments shorter than ``min_step`` m, standing still, are
  skipped, so a turn on the spot counts as one turn between the segments around it), divided
  by the path length: the length-weighted mean curvature, ``1/R`` on a circle of radius ``R``
  (Bench-MR's "angle over length"; "mean curvature" in MRPB).
* **Time within the safety distance** ``time_near_obstacles_s``: the simulated time during
  which the robot's edge was closer than ``safety_distance_m`` to true geometry; sample ``k``
  counts for ``t[k+1] - t[k]`` (MRPB's and Arena-Rosnav's "time in a safety zone").
* **Planner compute time per control cycle**: mean and 95th percentile (linear interpolation)
  of the wall-clock time of each ``act()`` call, ms (MRPB's computation time; the first
  cycle's ``reset`` is not included). Wall-clock: these two fields, like ``wall_s``, differ
  between replays of the same episode.

Metrics that need more samples than the trace has (an episode of a few cycles) are ``None``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

MIN_STEP_M = 1e-3  # path segments shorter than this count as standing still


def _clean(t: np.ndarray, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Samples with strictly increasing time (a repeated time stamp is dropped)."""
    t = np.asarray(t, dtype=float)
    pose = np.asarray(pose, dtype=float).reshape(len(t), -1)
    if len(t) == 0:
        return t, pose
    keep = np.concatenate([[True], np.diff(t) > 1e-12])
    return t[keep], pose[keep]


def velocities(t: np.ndarray, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(tm, v, omega): interval midpoint times (s), linear (m/s) and angular (rad/s) velocities
    of (T, 3) poses at times ``t`` (T,). Each has T - 1 entries."""
    t, pose = _clean(t, pose)
    dt = np.diff(t)
    dyaw = np.remainder(np.diff(pose[:, 2]) + math.pi, 2 * math.pi) - math.pi
    mid = pose[:-1, 2] + dyaw / 2
    d = np.diff(pose[:, :2], axis=0)
    v = (d[:, 0] * np.cos(mid) + d[:, 1] * np.sin(mid)) / dt
    return (t[:-1] + t[1:]) / 2, v, dyaw / dt


def derivative(t: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(midpoint times, dx/dt) by finite differences of samples ``x`` at times ``t``."""
    t, x = np.asarray(t, dtype=float), np.asarray(x, dtype=float)
    return (t[:-1] + t[1:]) / 2, np.diff(x) / np.diff(t)


def accelerations(t: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """Linear accelerations (m/s^2) along a trajectory (T - 2 of them)."""
    tm, v, _ = velocities(t, pose)
    return derivative(tm, v)[1]


def integrated_squared_jerk(t: np.ndarray, rate: np.ndarray) -> float | None:
    """``sum j^2 dt`` of the jerk ``j = d^2 rate / dt^2`` of a velocity ``rate`` sampled at ``t``
    (m^2/s^5 for a linear, rad^2/s^5 for an angular velocity); None with fewer than 4 samples."""
    if len(rate) < 4:
        return None
    ta, acc = derivative(t, rate)
    _, jerk = derivative(ta, acc)
    widths = np.diff(ta)  # each jerk sample stands for the interval between two accelerations
    return float(np.sum(jerk ** 2 * widths))


def angle_over_length(xy: np.ndarray, min_step: float = MIN_STEP_M) -> float | None:
    """Sum of the absolute turning angles between consecutive path segments (rad) over the
    path length (m): ``1/R`` on a circle of radius R. None for a path shorter than ``min_step``."""
    d = np.diff(np.asarray(xy, dtype=float).reshape(-1, 2), axis=0)
    length = np.hypot(d[:, 0], d[:, 1])
    moving = d[length >= min_step]
    total = float(length.sum())
    if total < min_step:
        return None
    if len(moving) < 2:
        return 0.0
    heading = np.arctan2(moving[:, 1], moving[:, 0])
    turn = np.abs(np.remainder(np.diff(heading) + math.pi, 2 * math.pi) - math.pi)
    return float(turn.sum() / total)


def time_within(t: np.ndarray, clearance: np.ndarray, distance: float) -> float:
    """Seconds during which ``clearance`` (T,) was below ``distance``; sample ``k`` lasts
    ``t[k+1] - t[k]`` (the last sample, the end of the episode, lasts nothing)."""
    t, clearance = np.asarray(t, dtype=float), np.asarray(clearance, dtype=float)
    if len(t) < 2:
        return 0.0
    return float(np.sum(np.diff(t)[clearance[:-1] < distance]))


def compute_ms(plan_s: np.ndarray) -> tuple[float | None, float | None]:
    """(mean, 95th percentile) of per-cycle planning times given in s, in ms; NaN entries (cycles
    without a planner call) are skipped; (None, None) without any."""
    ms = np.asarray(plan_s, dtype=float) * 1000.0
    ms = ms[np.isfinite(ms)]
    if len(ms) == 0:
        return None, None
    return float(ms.mean()), float(np.percentile(ms, 95))


def motion_metrics(t: np.ndarray, pose: np.ndarray, clearance: np.ndarray, plan_s: np.ndarray,
                   safety_distance_m: float) -> dict[str, Any]:
    """The result row's motion fields, from a trace's times ``t`` (T,), true poses (T, 3),
    edge clearances (T,) (m) and per-cycle planning times (s)."""
    tc, pc = _clean(t, pose)
    tm, v, omega = velocities(tc, pc) if len(tc) >= 2 else (np.zeros(0),) * 3
    acc = derivative(tm, v)[1] if len(v) >= 2 else np.zeros(0)
    mean_ms, p95_ms = compute_ms(plan_s)
    return {
        "accel_mean_mps2": float(np.abs(acc).mean()) if len(acc) else None,
        "accel_max_mps2": float(np.abs(acc).max()) if len(acc) else None,
        "jerk_linear": integrated_squared_jerk(tm, v),
        "jerk_angular": integrated_squared_jerk(tm, omega),
        "curvature_per_m": angle_over_length(pc[:, :2]) if len(pc) else None,
        "time_near_obstacles_s": time_within(t, clearance, safety_distance_m),
        "plan_ms_mean": mean_ms,
        "plan_ms_p95": p95_ms,
    }


# the row's motion fields, their units and one line each (the README and the report use them)
MOTION_FIELDS: dict[str, tuple[str, str]] = {
    "accel_mean_mps2": ("m/s^2", "mean |linear acceleration|"),
    "accel_max_mps2": ("m/s^2", "largest |linear acceleration|"),
    "jerk_linear": ("m^2/s^5", "integral of squared linear jerk"),
    "jerk_angular": ("rad^2/s^5", "integral of squared angular jerk"),
    "curvature_per_m": ("rad/m", "angle over length: turning per metre travelled"),
    "time_near_obstacles_s": ("s", "time with the robot's edge within safety_distance_m of geometry"),
    "plan_ms_mean": ("ms", "mean planner compute time per control cycle (wall clock)"),
    "plan_ms_p95": ("ms", "95th percentile of the planner compute time per cycle (wall clock)"),
}
