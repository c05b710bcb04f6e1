"""DWA and DWA under a D* Lite path: roll-outs, admissible velocities, the dynamic window, and
driving (stops before a wall, passes a 1 m door, goes round a wall with the global path).

Runtime: ~10 s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.planners.dwa import (
    DWA,
    DWAGlobal,
    arc_clearances,
    choose_velocity,
    edge_clearance,
    rollout,
)
from nav_bench.testing.harness import BoxWorld, run, wall_world

P = DWA().settings  # the defaults, as the planner reads them


def test_rollout_follows_straight_lines_and_circles() -> None:
    arcs = rollout(np.array([1.0, 2.0, 0.0]), np.array([0.5, 1.0]), np.array([0.0, 1.0]), 10,
                   math.pi / 10)
    assert arcs.shape == (2, 10, 3)
    np.testing.assert_allclose(arcs[0, -1], [1.0 + 0.5 * math.pi, 2.0, 0.0], atol=1e-12)
    # v = 1, omega = 1: a unit circle to the left; after pi s the robot is 2 m up, facing back
    np.testing.assert_allclose(arcs[1, -1], [1.0, 4.0, math.pi], atol=1e-12)
    np.testing.assert_allclose(np.hypot(arcs[1, :, 0] - 1.0, arcs[1, :, 1] - 3.0), 1.0, atol=1e-12)


def test_clearance_is_measured_from_the_robot_edge() -> None:
    arcs = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]])
    clear = arc_clearances(arcs, np.array([[2.0, 0.0], [0.0, 3.0]]), radius=0.2)
    np.testing.assert_allclose(clear, [[1.8, 0.8]])
    assert np.isinf(arc_clearances(arcs, np.zeros((0, 2)), 0.2)).all()


def test_the_clearance_of_one_pose_is_the_roll_out_clearance_of_that_pose() -> None:
    # choose_velocity's "already this close" clearance: the same value, to the last bit, as
    # arc_clearances' k-d tree query would give for the pose
    rng = np.random.default_rng(2)
    for _ in range(50):
        pose = rng.uniform(-5.0, 5.0, 3)
        points = pose[:2] + rng.uniform(-1.7, 1.7, (int(rng.integers(1, 150)), 2))
        expected = arc_clearances(pose[None, None, :], points, 0.2)[0, 0]
        assert edge_clearance(pose[:2], points, 0.2) == expected
    assert edge_clearance(np.zeros(2), np.zeros((0, 2)), 0.2) == math.inf


def test_the_window_limits_acceleration_and_free_space_takes_its_top() -> None:
    pose, goal = np.zeros(3), np.array([5.0, 0.0])
    c = choose_velocity(pose, goal, 0.2, 0.0, np.zeros((0, 2)), 0.2, 0.1, P, 0.5, 1.0)
    assert c.v == pytest.approx(0.2 + P.acc_v * 0.1) and c.omega == 0.0  # straight at the goal
    c = choose_velocity(pose, goal, 0.5, 0.0, np.zeros((0, 2)), 0.2, 0.1, P, 0.5, 1.0)
    assert c.v == pytest.approx(0.5)  # never above v_max
    c = choose_velocity(pose, np.array([0.0, 5.0]), 0.0, 0.0, np.zeros((0, 2)), 0.2, 0.1, P, 0.5, 1.0)
    assert c.omega == pytest.approx(P.acc_omega * 0.1)  # turns toward a goal on the left, as fast as allowed


def test_only_velocities_that_can_stop_in_time_are_admissible() -> None:
    # a wall of points 0.45 m ahead of a robot of radius 0.2 moving at 0.4 m/s: 0.25 m of edge
    # clearance, 0.20 m to the 0.05 m collision line; stopping from v needs 0.1 v + v^2 / 1.0
    wall = np.stack([np.full(41, 0.45), np.linspace(-2.0, 2.0, 41)], axis=1)
    c = choose_velocity(np.zeros(3), np.array([5.0, 0.0]), 0.4, 0.0, wall, 0.2, 0.1, P, 0.5, 1.0)
    assert c.v < 0.4  # it slows down
    assert 0.1 * c.v + c.v ** 2 / (2 * P.acc_v) <= 0.20 + 0.02  # and can still stop before the line
    far = wall + np.array([2.0, 0.0])
    c = choose_velocity(np.zeros(3), np.array([5.0, 0.0]), 0.4, 0.0, far, 0.2, 0.1, P, 0.5, 1.0)
    assert c.v == pytest.approx(0.45)


@pytest.mark.parametrize("seed", [0, 1])
def test_stops_before_a_wall(seed: int) -> None:
    # a 1.2 m wide dead-end corridor; the goal lies beyond its end wall (x = 4)
    world = BoxWorld.room((6.0, 1.2), [(4.0, 0.0, 6.0, 1.2)])
    result = run(DWA(), world, (1.0, 0.6, 0.0), (5.0, 0.6), time_s=20.0, seed=seed, noise_std=0.01)
    assert not result.reached and result.collisions == 0
    x = result.poses[:, 0]
    assert x.max() < 4.0 - 0.2 - 0.02  # the body's front never reached the wall
    first_stop = int(np.argmax((result.commands[:, 0] == 0.0) & (np.arange(len(result.commands)) > 5)))
    assert first_stop > 0 and 3.3 < x[first_stop] < 3.8  # it drove up, then stopped in front of the wall
    assert result.commands[:, 0].max() == pytest.approx(0.5)  # at full speed on the way
    assert result.kinds("blocked") >= 1


@pytest.mark.parametrize("cls", [DWA, DWAGlobal], ids=["dwa", "dwa_global"])
def test_passes_a_1m_door(cls: type) -> None:
    # a wall across an 8 x 6 m room with a 1.0 m door (y 2.5..3.5); start and goal on either side
    world = BoxWorld.room((8.0, 6.0), [(3.9, 0.0, 4.1, 2.5), (3.9, 3.5, 4.1, 6.0)])
    result = run(cls(), world, (1.0, 2.0, 0.0), (7.0, 4.0), time_s=60.0, noise_std=0.01)
    assert result.reached and result.collisions == 0
    crossing = result.poses[np.argmax(result.poses[:, 0] > 4.0)]
    assert 2.5 + 0.2 < crossing[1] < 3.5 - 0.2  # through the door, body inside its frame
    assert result.time < 30.0 and result.path_length < 9.0  # straight line 6.3 m


def test_global_path_leads_round_a_wall_that_traps_plain_dwa() -> None:
    world, start, goal = wall_world()
    result = run(DWAGlobal(), world, start, goal, time_s=60.0, noise_std=0.01)
    assert result.reached and result.collisions == 0
    assert result.kinds("replan") >= 1  # D* Lite repaired its path as the wall came into view
    state = result.planner.debug_state()
    assert state["path"].shape[1] == 2 and state["pmo"].shape == (60, 80)


def test_use_grid_adds_the_occupied_cells_as_obstacles() -> None:
    world = BoxWorld.room((6.0, 1.2), [(4.0, 0.0, 6.0, 1.2)])
    plain = run(DWA(), world, (1.0, 0.6, 0.0), (5.0, 0.6), time_s=6.0)
    gridded = run(DWA(use_grid=True), world, (1.0, 0.6, 0.0), (5.0, 0.6), time_s=6.0)
    assert "pmo" not in plain.planner.debug_state()
    pmo = gridded.planner.debug_state()["pmo"]
    assert (pmo[:, 39:41] > 65).any()  # the end wall at x = 4 m is in the grid
    obs_pts = len(gridded.planner.memory)
    assert obs_pts > 0 and gridded.collisions == plain.collisions == 0
