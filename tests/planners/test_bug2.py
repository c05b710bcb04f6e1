"""Bug2 on the kinematic harness: around a wall, out of a U, a goal it cannot reach, and a
lap round a pillar beside the wall it hit, which is not a proof of that.

Runtime: ~1 s.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from nav_bench.planners.bug2 import FOLLOW, GO, UNREACHABLE, Bug2, swept_angle
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
    assert result.kinds("unreachable") == 1 and result.kinds("lap") == 0
    planner = result.planner
    assert planner.mode == UNREACHABLE
    (_, t_stop, where), = [e for e in result.events if e[0] == "unreachable"]
    assert math.dist((where["x"], where["y"]), planner.hit) < 0.4  # back at the hit point
    stopped = result.commands[round(t_stop / 0.1) + 1:]
    assert len(stopped) > 0 and np.all(stopped == 0.0)


def pillar_beside_a_wall() -> tuple[BoxWorld, tuple[float, float, float], tuple[float, float]]:
    """very_complex's trap in a 6 x 6.5 m room: the m-line (start (1, 1), goal (4.5, 4.5)) meets
    a wall (y = 3.425..3.575, x = 2.4..6, joined to the right-hand wall) diagonally, with a
    0.6 m square pillar whose centre is 1 m right of the hit point; the goal is above the wall,
    reached round its left end."""
    world = BoxWorld.room((6.0, 6.5), [(2.4, 3.425, 6.0, 3.575), (3.3, 1.9, 3.9, 2.5)])
    return world, (1.0, 1.0, math.pi / 4), (4.5, 4.5)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_lap_round_a_pillar_beside_the_hit_wall_is_not_unreachable(seed: int) -> None:
    """Issue 12 (very_complex seeds 1 and 3 on main, 369d2f7): the follower keeps the nearest
    echo on its side, which at the hit is the pillar's; the robot laps the pillar and is back
    at the hit point. That lap leaves the goal outside, so it proves nothing: the robot goes on,
    follows the wall it hit this time, and reaches the goal (main stopped at 19.8-19.9 s with
    "unreachable": results/baselines/bug2_s13/README.md)."""
    world, start, goal = pillar_beside_a_wall()
    result = run(Bug2(), world, start, goal, time_s=60.0, seed=seed, noise_std=0.01)
    assert result.kinds("unreachable") == 0
    (_, t_lap, where), = [e for e in result.events if e[0] == "lap"]  # the lap round the pillar
    assert 15.0 < t_lap < 25.0 and where["goal_enclosed"] is False
    hits = [e for e in result.events if e[0] == "replan"]
    assert len(hits) == 2  # the hit on the wall, and the same wall hit again after the lap
    assert math.dist((hits[1][2]["x"], hits[1][2]["y"]), (hits[0][2]["x"], hits[0][2]["y"])) < 0.5
    xy = result.poses[:, :2]
    lap = xy[: round(t_lap / 0.1)]
    assert lap[:, 0].max() > 3.9 + 0.3 and lap[:, 1].min() < 1.9 - 0.2  # it went round the pillar
    after = xy[round(t_lap / 0.1):]
    assert after[:, 0].min() < 2.4 - 0.3  # then round the wall's left end
    assert result.reached and result.collisions == 0


def test_the_lap_test_counts_the_turns_round_the_goal() -> None:
    """``swept_angle`` summed over a closed path: 2 pi per turn round the goal, 0 when the
    goal is outside (the square below, travelled clockwise as a right-hand follower laps)."""
    square = np.array([(0.0, 0.0), (0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)])
    steps = np.linspace(0.0, 1.0, 11)[1:]
    path = [square[0]] + [a + f * (b - a) for a, b in itertools.pairwise(square) for f in steps]

    def turns(goal: tuple[float, float]) -> float:
        g = np.asarray(goal)
        return sum(swept_angle(a, b, g) for a, b in itertools.pairwise(path)) / (2 * math.pi)

    assert turns((0.5, 0.5)) == pytest.approx(-1.0)
    assert turns((1.5, 0.5)) == pytest.approx(0.0, abs=1e-12)
    assert turns((0.5, 3.0)) == pytest.approx(0.0, abs=1e-12)


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
