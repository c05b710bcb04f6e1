"""Motion metrics on hand-made traces with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.episode.motion import (
    accelerations,
    angle_over_length,
    compute_ms,
    integrated_squared_jerk,
    motion_metrics,
    time_within,
    velocities,
)

DT = 0.1


def straight(n: int = 50, v: float = 0.4) -> tuple[np.ndarray, np.ndarray]:
    t = DT * np.arange(n)
    pose = np.stack([1.0 + v * t * math.cos(0.3), 2.0 + v * t * math.sin(0.3), np.full(n, 0.3)], axis=1)
    return t, pose


def circle(radius: float, v: float = 0.5, n: int = 200) -> tuple[np.ndarray, np.ndarray]:
    t = DT * np.arange(n)
    w = v / radius
    th = w * t
    pose = np.stack([radius * np.sin(th), radius * (1 - np.cos(th)), np.remainder(th + math.pi, 2 * math.pi) - math.pi],
                    axis=1)
    return t, pose


def test_a_straight_constant_speed_line_has_no_acceleration_jerk_or_turning() -> None:
    t, pose = straight()
    _, v, w = velocities(t, pose)
    np.testing.assert_allclose(v, 0.4, atol=1e-12)
    np.testing.assert_allclose(w, 0.0, atol=1e-12)
    m = motion_metrics(t, pose, np.full(len(t), 1.0), np.full(len(t), 0.002), 0.3)
    assert m["accel_mean_mps2"] == pytest.approx(0.0, abs=1e-9)
    assert m["accel_max_mps2"] == pytest.approx(0.0, abs=1e-9)
    assert m["jerk_linear"] == pytest.approx(0.0, abs=1e-9)
    assert m["jerk_angular"] == pytest.approx(0.0, abs=1e-9)
    assert m["curvature_per_m"] == pytest.approx(0.0, abs=1e-9)
    assert m["time_near_obstacles_s"] == 0.0
    assert m["plan_ms_mean"] == pytest.approx(2.0) and m["plan_ms_p95"] == pytest.approx(2.0)


@pytest.mark.parametrize("radius", [0.5, 2.0])
def test_a_circle_of_radius_r_has_curvature_one_over_r(radius: float) -> None:
    t, pose = circle(radius)
    # 200 samples: 199 chords of 2 R sin(d/2) with d = 0.05 / R rad, and 198 turns of d between them
    d = 0.5 * DT / radius
    assert angle_over_length(pose[:, :2]) == pytest.approx(198 * d / (199 * 2 * radius * math.sin(d / 2)))
    assert angle_over_length(pose[:, :2]) == pytest.approx(1.0 / radius, rel=0.01)
    _, v, w = velocities(t, pose)
    np.testing.assert_allclose(w, 0.5 / radius, rtol=1e-9)  # constant turn rate, wrapped yaw and all
    np.testing.assert_allclose(v, v[0], rtol=1e-9)
    m = motion_metrics(t, pose, np.full(len(t), 1.0), np.zeros(len(t)), 0.3)
    assert m["accel_max_mps2"] == pytest.approx(0.0, abs=1e-9)  # constant speed on the circle
    assert m["jerk_angular"] == pytest.approx(0.0, abs=1e-9)


def test_constant_acceleration_and_a_known_jerk() -> None:
    t = DT * np.arange(40)
    x = 0.5 * 0.2 * t ** 2  # a = 0.2 m/s^2 from rest
    pose = np.stack([x, np.zeros_like(t), np.zeros_like(t)], axis=1)
    np.testing.assert_allclose(accelerations(t, pose), 0.2, rtol=1e-9)
    assert integrated_squared_jerk(velocities(t, pose)[0], velocities(t, pose)[1]) == pytest.approx(0.0, abs=1e-9)
    # v = t^2 / 2: a = t, jerk = 1 m/s^3 throughout; the integral of 1^2 over the jerk samples' span
    tm = DT * np.arange(30)
    assert integrated_squared_jerk(tm, tm ** 2 / 2) == pytest.approx(DT * 28, rel=1e-9)  # 28 jerk samples
    assert integrated_squared_jerk(tm[:3], tm[:3]) is None  # too few samples


def test_turning_on_the_spot_counts_once_between_the_segments_around_it() -> None:
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 1.0]])  # 90 deg turn at (1, 0)
    assert angle_over_length(xy) == pytest.approx((math.pi / 2) / 2.0)
    assert angle_over_length(np.zeros((5, 2))) is None


def test_time_within_the_safety_distance() -> None:
    t = DT * np.arange(11)  # 1 s
    clearance = np.array([1.0, 0.5, 0.29, 0.2, 0.1, 0.25, 0.31, 0.4, 0.2, 1.0, 0.0])
    # below 0.3 m: samples 2, 3, 4, 5 and 8 (the last sample lasts nothing) -> 5 x 0.1 s
    assert time_within(t, clearance, 0.3) == pytest.approx(0.5)
    assert time_within(t, clearance, 0.05) == pytest.approx(0.0)


def test_compute_time_mean_and_p95_skip_cycles_without_a_call() -> None:
    plan_s = np.array([0.001] * 19 + [0.021, math.nan])
    mean, p95 = compute_ms(plan_s)
    assert mean == pytest.approx(2.0)
    assert p95 == pytest.approx(np.percentile([1.0] * 19 + [21.0], 95))
    assert compute_ms(np.array([math.nan])) == (None, None)


def test_every_row_carries_the_motion_metrics_of_its_trace() -> None:
    from pathlib import Path

    from nav_bench.episode.loop import run_episode
    from nav_bench.episode.settings import EpisodeSettings
    from nav_bench.specs import PlannerSetSpec
    from nav_bench.world.load import load_world

    world = load_world(Path(__file__).resolve().parents[2] / "worlds" / "paper" / "open_room.yaml")
    result = run_episode(world, PlannerSetSpec(planner="goal_seek"), seed=0,
                         settings=EpisodeSettings(safety_distance_m=0.5))
    row, trace = result.row, result.trace
    assert row.success and row.settings["safety_distance_m"] == 0.5
    # goal_seek drives a straight line in the open room: little turning, the drive's 1 m/s^2 at most
    assert row.curvature_per_m < 0.02
    assert 0.0 < row.accel_mean_mps2 < row.accel_max_mps2 <= 1.0 * 1.2
    assert row.time_near_obstacles_s == 0.0 and row.min_clearance_m > 0.5
    assert len(trace.plan_s) == len(trace.t) and np.isnan(trace.plan_s[-1])
    assert row.plan_ms_mean == pytest.approx(1000 * np.nanmean(trace.plan_s))
    assert row.plan_ms_p95 > 0
    stored = row.to_json()
    assert set(stored) >= {"accel_mean_mps2", "jerk_linear", "jerk_angular", "plan_ms_p95"}
