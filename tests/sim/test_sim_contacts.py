"""Collisions: distinct contact episodes of the robot with anything but the floor."""

from __future__ import annotations

import numpy as np
import pytest
from sim_helpers import make_sim, make_world

from nav_bench.interface import Command
from nav_bench.sim import Simulation
from nav_bench.sim.contacts import ContactEpisodes

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


def test_contact_window_is_the_clearance_over_the_closing_speed(session, exact_robot):
    from nav_bench.sim.contacts import CLEARANCE_MARGIN

    mover = {"shape": {"cylinder": {"radius": 0.25}}, "path": [[8.0, 2.0], [8.0, 8.0]],
             "speed": 0.4, "mode": "pingpong"}
    sim = make_sim(session, make_world(start=(2.0, 5.0, 0.0), obstacles=[WALL_AHEAD],
                                       movers=[mover]), exact_robot)
    window = sim._contact_window
    model = sim.robot.model
    rim = max(model.wheel_radius) * exact_robot.drive.max_wheel_speed  # 0.75 m/s
    assert window.closing_speed == pytest.approx(
        1.25 * rim * (1 + 2 * model.radius / model.wheel_base) + 0.4)
    movers = np.array([[8.0, 2.0]])
    # wall face at x = 3.0: 1 m from the centre, 0.82 m from the robot's edge
    assert window.clearance(np.array([2.0, 5.0]), movers) == pytest.approx(0.82)
    assert window.free_for(np.array([2.0, 5.0]), movers) == pytest.approx(
        (0.82 - CLEARANCE_MARGIN) / window.closing_speed)
    # the mover is nearer here: 0.5 m centre to centre - 0.25 - 0.18
    assert window.clearance(np.array([8.0, 2.5]), movers) == pytest.approx(0.07)
    assert window.free_for(np.array([2.9, 5.0]), movers) == 0.0  # 0.08 m to the wall: too near


def test_skipping_contact_reads_when_clear_counts_the_same_collisions(session, exact_robot):
    """Drive into walls, spin beside them and let a mover run over the robot: the collisions
    and the touching state after every control cycle are those of reading every step."""
    mover = {"shape": {"box": {"size": [0.4, 0.4]}}, "path": [[2.0, 5.1], [8.0, 5.1]],
             "speed": 0.5, "mode": "pingpong"}
    world = make_world(start=(5.0, 5.0, 0.0), movers=[mover], boundary=True,
                       obstacles=[{"cylinder": {"center": [5.0, 3.5], "radius": 0.4}}])
    commands = ([Command(0.0, 0.0)] * 70 + [Command(0.5, 0.0)] * 30 + [Command(-0.2, 1.0)] * 20
                + [Command(0.0, 0.0)] * 20 + [Command(0.6, -0.4)] * 60 + [Command(0.0, 2.0)] * 20
                + [Command(0.4, 0.0)] * 80)
    states = {}
    for mode in ("every_step", "when_near"):
        sim = Simulation(session, world, exact_robot, np.random.default_rng(0), contact_checks=mode)
        seen = []
        for cmd in commands:
            sim.apply(cmd)
            sim.step(24)
            seen.append((sim.collisions, sim.contact_now))
        states[mode] = (seen, sim.contact_reads, sim._steps)
    every, near = states["every_step"], states["when_near"]
    assert near[0] == every[0]
    assert every[0][-1][0] >= 3  # the mover, the cylinder and the boundary walls were hit
    assert every[1] == every[2]  # every step read
    assert near[1] < near[2]


def test_no_contacts_are_read_far_from_everything(session, exact_robot):
    sim = make_sim(session, make_world(start=(5.0, 5.0, 0.0), boundary=True), exact_robot)
    sim.apply(Command(0.1, 0.5))  # a small circle in the middle of the room
    for _ in range(100):
        sim.step(24)
    assert sim.contact_reads == 0 and sim.collisions == 0
