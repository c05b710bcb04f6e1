"""Collisions: distinct contact episodes of the robot with anything but the floor."""

from __future__ import annotations

import pytest
from sim_helpers import make_sim, make_world

from nav_bench.planners.base import Command
from nav_bench.sim.simulation import ContactEpisodes

WALL_AHEAD = {"wall": {"from": [3.1, 1.0], "to": [3.1, 9.0], "thickness": 0.2}}  # face x = 3.0


def test_contact_episodes_count_once_per_touch():
    episodes = ContactEpisodes()
    counts = [episodes.update(b) for b in ([], [7], [7], [7, 9], [9], [], [7], [7])]
    assert counts == [0, 1, 0, 1, 0, 0, 1, 0]
    assert episodes.count == 3 and episodes.touching == {7}


def test_pressing_against_a_wall_is_one_collision_and_hitting_again_is_two(session, exact_robot):
    sim = make_sim(session, make_world(start=(2.0, 5.0, 0.0), obstacles=[WALL_AHEAD]), exact_robot)
    sim.apply(Command(0.4, 0.0))
    sim.step(240 * 5)  # reaches the wall after ~2.5 s and keeps pushing
    assert sim.collisions == 1 and sim.contact_now
    assert sim.true_pose()[0] == pytest.approx(3.0 - 0.18, abs=0.003)  # stopped by the wall
    sim.apply(Command(-0.3, 0.0))
    sim.step(240)
    assert sim.collisions == 1 and not sim.contact_now
    sim.apply(Command(0.3, 0.3))  # hit again at an angle, sliding along the wall
    sim.step(240 * 4)
    assert sim.collisions == 2


def test_the_floor_is_not_a_collision(session, exact_robot):
    sim = make_sim(session, make_world(start=(5.0, 5.0, 0.0)), exact_robot)
    sim.apply(Command(0.5, 1.0))
    sim.step(240 * 3)
    assert sim.collisions == 0 and not sim.contact_now


def test_a_mover_running_into_the_robot_is_a_collision(session, exact_robot):
    mover = {"shape": {"box": {"size": [0.4, 0.4]}}, "path": [[2.0, 5.1], [8.0, 5.1]],
             "speed": 0.5, "mode": "pingpong"}
    sim = make_sim(session, make_world(start=(5.0, 5.0, 0.0), movers=[mover]), exact_robot)
    sim.step(240 * 5)  # the mover reaches the robot after ~5.2 s
    assert sim.collisions == 0
    sim.step(240 * 2)
    assert sim.collisions == 1 and sim.contact_now
    assert sim.true_pose()[0] > 5.3  # pushed along: the mover is kinematic
