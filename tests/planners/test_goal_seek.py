"""goal_seek: straight to the goal, slow down and stop before obstacles."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.errors import InputError, PlannerError
from nav_bench.planners.goal_seek import GoalSeek
from nav_bench.testing.harness import BoxWorld, open_room, run


def test_reaches_a_goal_in_an_open_room_starting_turned_away() -> None:
    world, start, goal = open_room()  # start faces 107 deg away from the goal direction
    result = run(GoalSeek(), world, start, goal, time_s=30.0)
    assert result.reached and result.collisions == 0
    straight = math.dist(start[:2], goal)
    assert result.path_length == pytest.approx(straight, rel=0.08)  # turns on the spot first
    assert result.time < straight / 0.5 + 6.0


def test_stops_before_a_wall_at_stop_distance_and_stays() -> None:
    world = BoxWorld.room((8.0, 6.0), [(4.0, 1.0, 4.15, 5.0)])
    result = run(GoalSeek(), world, (1.0, 3.0, 0.0), (7.0, 3.0), time_s=30.0)
    assert not result.reached and result.collisions == 0
    x_final = result.poses[-1, 0]
    assert 4.0 - x_final == pytest.approx(0.35, abs=0.02)  # centre to wall face = stop_distance
    assert np.all(result.commands[-50:, 0] == 0.0)  # stopped for good
    speeds = result.commands[:, 0]
    assert speeds.max() == pytest.approx(0.5)
    # slowing down: below full speed only within slow_distance of the wall
    slow = result.poses[:-1, 0][(speeds < 0.49) & (speeds > 0)]
    assert slow.min() > 4.0 - 0.8 - 0.05


def test_stops_at_the_goal() -> None:
    world, _, _ = open_room()
    planner = GoalSeek(goal_tolerance=0.3)
    result = run(planner, world, (1.0, 2.5, 0.0), (4.0, 2.5), time_s=20.0, goal_tolerance=0.05,
                 reset=True)
    # the harness demands 5 cm, the planner stops at 30 cm: it must stop there and stay
    assert not result.reached
    assert math.dist(result.poses[-1, :2], (4.0, 2.5)) == pytest.approx(0.3, abs=0.06)
    assert np.all(result.commands[-20:] == 0.0)


def test_parameters_are_checked() -> None:
    with pytest.raises(InputError, match="slow_distance"):
        GoalSeek(slow_distans=1.0)
    world, start, goal = open_room()
    with pytest.raises(PlannerError, match="slow_distance > stop_distance"):
        run(GoalSeek(slow_distance=0.3), world, start, goal, time_s=0.1)
