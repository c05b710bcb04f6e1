"""Bug2 on the kinematic harness: around a wall, out of a U, and a goal it cannot reach.

Runtime: ~0.5 s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.planners.bug2 import FOLLOW, GO, UNREACHABLE, Bug2
from nav_bench.testing.harness import BoxWorld, default_robot, observe, run, u_world, wall_world


@pytest.mark.parametrize("seed", [0, 1])
def test_gets_around_a_single_wall_and_leaves_on_the_m_line(seed: int) -> None:
    world, start, goal = wall_world()  # wall x = 3.9..4.1, y = 1.5..4.5; m-line y = 3
    result = run(Bug2(), world, start, goal, time_s=60.0, seed=seed, noise_std=0.01)
    assert result.reached and result.collisions == 0
    assert result.kinds("replan") == 1  # one hit point
    (_, t_hit, hit), = [e for e in result.events if e[0] == "replan"]
    assert hit["y"] == pytest.approx(3.0, abs=0.05)  # the hit point is on the m-line...
    assert 3.9 - hit["x"] == pytest.approx(0.55, abs=0.1)  # ...hit_distance before the wall
    xy = result.poses[:, :2]
    before = xy[: round(t_hit / 0.1)]
    assert np.abs(before[:, 1] - 3.0).max() < 0.02  # motion to goal follows the m-line
    # it went round one end of the wall: with the wall on its right, turning left = over the top
    assert xy[:, 1].max() > 4.5 + 0.3 and xy[:, 1].min() > 2.5
    # and left the wall where it crossed the m-line beyond it, then drove along the m-line
    after = xy[xy[:, 0] > 4.8]
    assert np.abs(after[:, 1] - 3.0).max() < 0.15
    assert result.path_length < 11.0


def test_wall_side_left_goes_round_the_other_end() -> None:
    world, start, goal = wall_world()
    result = run(Bug2(wall_side="left"), world, start, goal, time_s=60.0)
    assert result.reached and result.collisions == 0
    assert result.poses[:, 1].min() < 1.5 - 0.3 and result.poses[:, 1].max() < 3.5


def test_escapes_a_u_shaped_obstacle_with_the_goal_behind_it() -> None:
    world, start, goal = u_world()  # U open toward the start, goal behind its bottom
    result = run(Bug2(), world, start, goal, time_s=120.0, seed=2, noise_std=0.01)
    assert result.reached and result.collisions == 0
    xy = result.poses[:, :2]
    assert xy[:, 0].max() > 7.5 and (xy[:, 0] > 4.0).any()
    assert np.any((xy[:, 0] > 3.0) & (xy[:, 0] < 5.0) & (np.abs(xy[:, 1] - 4.0) < 0.3))  # went in
    assert result.kinds("replan") == 1  # one hit at the bottom, then one boundary walk out
    assert result.path_length < 20.0


def test_a_full_lap_around_an_enclosed_goal_means_unreachable() -> None:
    ring = [(5.0, 2.0, 6.6, 2.15), (5.0, 3.45, 6.6, 3.6), (5.0, 2.0, 5.15, 3.6), (6.45, 2.0, 6.6, 3.6)]
    world = BoxWorld.room((9.0, 6.0), ring)
    result = run(Bug2(), world, (1.0, 2.8, 0.0), (5.8, 2.8), time_s=80.0)
    assert not result.reached and result.collisions == 0
    assert result.kinds("unreachable") == 1
    planner = result.planner
    assert planner.mode == UNREACHABLE
    (_, t_stop, where), = [e for e in result.events if e[0] == "unreachable"]
    assert math.dist((where["x"], where["y"]), planner.hit) < 0.4  # back at the hit point
    stopped = result.commands[round(t_stop / 0.1) + 1:]
    assert len(stopped) > 0 and np.all(stopped == 0.0)


def test_mode_switches_at_the_hit_distance() -> None:
    robot = default_robot()
    world = BoxWorld.room((6.0, 4.0), [(3.0, 0.0, 3.2, 4.0)])
    bug = Bug2()
    far = observe(world, np.array([2.0, 2.0, 0.0]), np.array([5.0, 2.0]), robot, 0.0, 0.1)
    bug.reset(far, np.random.default_rng(0))
    cmd = bug.act(far)  # wall 1 m ahead: keep going
    assert bug.mode == GO and cmd.v > 0
    near = observe(world, np.array([2.5, 2.0, 0.0]), np.array([5.0, 2.0]), robot, 0.1, 0.1)
    cmd = bug.act(near)  # 0.5 m < hit_distance 0.55: follow the wall, turning left first
    assert bug.mode == FOLLOW and cmd.v == 0.0 and cmd.omega > 0


@pytest.mark.slow
def test_reaches_the_goal_through_a_generated_maze_in_the_simulator() -> None:
    """Issue 12: a backtracker maze of 1 m corridors (``nav-bench generate maze --seed 3``),
    where Bug2 timed out on main (78d21c7: its straight-wall fit lost the wall at every
    junction and it shuttled in the first corridors); the follower now keeps the wall."""
    from nav_bench.episode.loop import run_episode
    from nav_bench.specs import PlannerSetSpec
    from nav_bench.world.generate import generate_world
    from nav_bench.world.load import world_from_data

    world = world_from_data(generate_world("maze", 3))
    result = run_episode(world, PlannerSetSpec(planner="bug2"), seed=0)
    assert result.row.outcome == "reached", result.row
    assert result.row.collisions == 0
