"""TangentBug: its local range function, and the harness worlds (wall, U).

Runtime: ~1 s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.planners.bug2 import Bug2
from nav_bench.planners.tangent_bug import TangentBug, blocked_interval_edges, range_function
from nav_bench.testing.harness import run, u_world, wall_world


def test_range_function_grows_each_echo_by_the_clearance_radius() -> None:
    directions = np.radians(np.arange(-180.0, 180.0, 5.0))
    rho = range_function(np.array([[2.0, 0.0]]), np.zeros(2), 0.5, directions)
    half = math.degrees(math.asin(0.5 / 2.0))  # 14.48 deg
    blocked = np.degrees(directions[np.isfinite(rho)])
    assert blocked.min() == pytest.approx(-10.0) and blocked.max() == pytest.approx(10.0)
    assert half == pytest.approx(14.48, abs=0.01)
    assert np.all(rho[np.isfinite(rho)] == pytest.approx(2.0))
    # the nearer of two echoes on the same bearing defines rho
    rho2 = range_function(np.array([[2.0, 0.0], [1.0, 0.0]]), np.zeros(2), 0.5, np.array([0.0]))
    assert rho2[0] == pytest.approx(1.0)


def test_blocked_interval_edges_wrap_around() -> None:
    blocked = np.zeros(12, dtype=bool)
    blocked[[10, 11, 0, 1, 2]] = True
    assert blocked_interval_edges(blocked, 0) == (9, 3)  # first free clockwise, counter-clockwise
    assert blocked_interval_edges(np.ones(5, dtype=bool), 2) is None


@pytest.mark.parametrize("seed", [0, 1])
def test_gets_around_a_single_wall(seed: int) -> None:
    world, start, goal = wall_world()
    result = run(TangentBug(), world, start, goal, time_s=60.0, seed=seed, noise_std=0.01)
    assert result.reached and result.collisions == 0
    xy = result.poses[:, :2]
    assert xy[:, 1].min() < 1.5 - 0.2 or xy[:, 1].max() > 4.5 + 0.2  # round an end of the wall
    assert result.path_length < 11.0


def test_escapes_a_u_and_takes_a_shorter_way_than_bug2() -> None:
    world, start, goal = u_world()
    tangent = run(TangentBug(), world, start, goal, time_s=120.0, seed=3, noise_std=0.01)
    bug2 = run(Bug2(), world, start, goal, time_s=120.0, seed=3, noise_std=0.01)
    assert tangent.reached and tangent.collisions == 0 and bug2.reached
    assert tangent.kinds("replan") >= 1  # boundary following happened
    # leaves the boundary as soon as the goal is visibly reachable (d_reach < d_followed)
    assert tangent.path_length < bug2.path_length - 1.5


def test_stops_following_when_the_goal_is_reachable() -> None:
    world, start, goal = wall_world()
    result = run(TangentBug(), world, start, goal, time_s=60.0)
    planner = result.planner
    assert planner.mode == "motion_to_goal"
    # after the wall end it heads straight for the goal: the last 2 m are a straight segment
    tail = result.poses[np.hypot(*(result.poses[:, :2] - goal).T) < 2.0, :2]
    direction = (goal - tail[0]) / np.linalg.norm(goal - tail[0])
    rel = tail - tail[0]
    lateral = np.abs(rel[:, 0] * direction[1] - rel[:, 1] * direction[0])
    assert lateral.max() < 0.1
