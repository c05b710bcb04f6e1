"""Artificial potential field: forces by hand, and the local minimum it is known for.

Runtime: ~0.5 s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.interface import Observation
from nav_bench.planners.apf import PotentialField, attractive_force, repulsive_force
from nav_bench.testing.harness import default_robot, open_room, run, u_world


def test_attraction_is_quadratic_near_and_conic_far() -> None:
    assert attractive_force(np.zeros(2), np.array([0.5, 0.0]), 1.0, 1.0) == pytest.approx([0.5, 0.0])
    far = attractive_force(np.zeros(2), np.array([3.0, 4.0]), 2.0, 1.0)
    assert far == pytest.approx([2.0 * 0.6, 2.0 * 0.8])  # k_att * radius along the unit vector
    assert np.hypot(*attractive_force(np.zeros(2), np.array([1.0, 0.0]), 2.0, 1.0)) == pytest.approx(2.0)


def test_repulsion_by_hand() -> None:
    # echo 0.7 m ahead of a 0.2 m robot: rho = 0.5 m, rho0 = 0.8 m, k_rep = 0.05
    # |F| = 0.05 (1/0.5 - 1/0.8) / 0.5^2 = 0.05 * 0.75 * 4 = 0.15, pointing back
    f = repulsive_force(np.zeros(2), np.array([[0.7, 0.0]]), 0.2, 0.05, 0.8, 0.05)
    assert f == pytest.approx([-0.15, 0.0])
    # beyond the influence distance: nothing; symmetric echoes cancel sideways
    assert repulsive_force(np.zeros(2), np.array([[1.2, 0.0]]), 0.2, 0.05, 0.8, 0.05) == pytest.approx([0, 0])
    pair = repulsive_force(np.zeros(2), np.array([[0.5, 0.5], [0.5, -0.5]]), 0.2, 0.05, 0.8, 0.05)
    assert pair[1] == pytest.approx(0.0, abs=1e-12) and pair[0] < 0
    # clearance floor keeps it finite when an echo touches the body
    touching = repulsive_force(np.zeros(2), np.array([[0.2, 0.0]]), 0.2, 0.05, 0.8, 0.05)
    assert touching[0] == pytest.approx(-0.05 * (1 / 0.05 - 1 / 0.8) / 0.05 ** 2)


def test_forces_from_an_observation() -> None:
    robot = default_robot()  # sonars on the 0.2 m body edge
    ranges = np.full(6, robot.sonar.max_range)
    ranges[[2, 3]] = 0.5  # both front sonars (-15, +15 deg): echoes 0.7 m from the centre
    obs = Observation(t=0.0, pose=np.array([1.0, 1.0, 0.0]), goal=np.array([4.0, 1.0]), ranges=ranges,
                      robot=robot, bounds=(0.0, 0.0, 5.0, 2.0), dt=0.1)
    planner = PotentialField()
    planner.reset(obs, np.random.default_rng(0))
    f_att, f_rep = planner.forces(obs)
    assert f_att == pytest.approx([1.0, 0.0])  # goal 3 m away, conic: k_att * attract_radius
    per_echo = 0.05 * (1 / 0.5 - 1 / 0.8) / 0.25
    assert f_rep == pytest.approx([-2 * per_echo * math.cos(math.radians(15)), 0.0], abs=1e-12)
    cmd = planner.act(obs)
    total = 1.0 - 2 * per_echo * math.cos(math.radians(15))
    assert cmd.omega == pytest.approx(0.0, abs=1e-12)
    assert cmd.v == pytest.approx(min(0.4, 0.5 * total))


def test_reaches_the_goal_in_an_open_room() -> None:
    world, start, goal = open_room()
    result = run(PotentialField(), world, start, goal, time_s=40.0)
    assert result.reached and result.collisions == 0


def test_trapped_in_a_u_as_expected() -> None:
    """Expected behaviour, not a bug: the field has a minimum inside the U (Khatib 1986, and
    Koren & Borenstein 1991 on potential-field limitations). There is no escape rule."""
    world, start, goal = u_world()
    result = run(PotentialField(), world, start, goal, time_s=60.0, noise_std=0.01)
    assert not result.reached and result.collisions == 0
    last = result.poses[-100:, :2]  # the last 10 s
    assert np.all((last[:, 0] > 3.0) & (last[:, 0] < 5.0) & (np.abs(last[:, 1] - 4.0) < 1.2))
    assert np.ptp(last[:, 0]) < 0.3 and np.ptp(last[:, 1]) < 0.3  # at rest where forces balance
    assert result.kinds("replan") == 0
