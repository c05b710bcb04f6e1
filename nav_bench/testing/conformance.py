"""What every planner must do, as plain checks (an ``AssertionError`` names what broke).

``tests/planners/test_conformance.py`` runs them on every registered planner; run them on
yours with ``check_planner(MyPlanner)`` or one at a time from your own tests. All use the
kinematic harness (:mod:`nav_bench.testing.harness`); together ~1 s per planner.
"""

from __future__ import annotations

import math

import numpy as np

from nav_bench.interface import Command, Observation, RobotInfo
from nav_bench.planners.base import Param, Planner, resolve_params
from nav_bench.testing.harness import BoxWorld, default_robot, observe, open_room, run, u_world


def check_declares_its_parameters(cls: type[Planner]) -> None:
    """Unique parameter names, each a :class:`Param` with a unit, a doc line and a default
    that passes its own check."""
    names = [p.name for p in cls.params]
    assert len(names) == len(set(names)), "parameter names must be unique"
    for p in cls.params:
        assert isinstance(p, Param)
        assert isinstance(p.unit, str) and p.unit.strip(), f"{p.name}: no unit"
        assert isinstance(p.doc, str) and len(p.doc.strip()) > 5, f"{p.name}: no doc"
        assert p.check(p.default) == p.default, f"{p.name}: default fails its own check"
    assert resolve_params(cls, {}) == {p.name: p.default for p in cls.params}


def random_observation(rng: np.random.Generator, robot: RobotInfo, t: float) -> Observation:
    """Nonsense sensing: random pose and goal, some readings with no echo, some touching."""
    s = robot.sonar
    ranges = rng.uniform(s.min_range, s.max_range, len(s.angles))
    ranges[rng.random(len(ranges)) < 0.3] = s.max_range  # some "no echo"
    ranges[rng.random(len(ranges)) < 0.1] = s.min_range  # some touching
    pose = np.array([rng.uniform(0.5, 5.5), rng.uniform(0.5, 4.5), rng.uniform(-math.pi, math.pi)])
    return Observation(t=t, pose=pose, goal=np.array([rng.uniform(0.5, 5.5), rng.uniform(0.5, 4.5)]),
                       ranges=ranges, robot=robot, bounds=(0.0, 0.0, 6.0, 5.0), dt=0.1)


def check_commands_are_bounded(cls: type[Planner], v_max: float = 0.5,
                               omega_max: float = 2.0) -> None:
    """Finite commands within the robot's limits whatever it senses; a dict of debug state."""
    robot = default_robot(v_max=v_max, omega_max=omega_max)
    rng = np.random.default_rng(3)
    planner = cls()
    planner.reset(random_observation(rng, robot, 0.0), np.random.default_rng(0))
    for i in range(1, 150):  # nonsense sensing: jumps, touching readings, random goals
        cmd = planner.act(random_observation(rng, robot, 0.1 * i))
        assert isinstance(cmd, Command)
        assert math.isfinite(cmd.v) and math.isfinite(cmd.omega)
        assert abs(cmd.v) <= robot.v_max + 1e-9
        assert abs(cmd.omega) <= robot.omega_max + 1e-9
    assert isinstance(planner.debug_state(), dict)


def check_reaches_the_goal_in_an_open_room(cls: type[Planner]) -> None:
    """Reaches the goal of an empty room without touching anything, on a path < 2x straight."""
    world, start, goal = open_room()
    result = run(cls(), world, start, goal, time_s=60.0)
    assert result.reached, (f"{cls.name} ended {math.dist(result.poses[-1, :2], goal):.2f} m "
                            f"from the goal")
    assert result.collisions == 0
    assert result.path_length < 2.0 * math.dist(start[:2], goal)


def check_reset_forgets_the_previous_episode(cls: type[Planner]) -> None:
    """A planner reset after an episode acts exactly as a new one."""
    world, start, goal = open_room()
    used = cls()
    assert isinstance(used.debug_state(), dict)  # callable before the first reset
    u, u_start, u_goal = u_world()
    run(used, u, u_start, u_goal, time_s=15.0, seed=5, noise_std=0.02)  # leave state behind
    again = run(used, world, start, goal, time_s=20.0, seed=1, noise_std=0.01)
    fresh = run(cls(), world, start, goal, time_s=20.0, seed=1, noise_std=0.01)
    np.testing.assert_array_equal(again.commands, fresh.commands)
    assert again.events == fresh.events


def check_same_seed_same_commands(cls: type[Planner]) -> None:
    """The same seed gives the same commands and events."""
    world = BoxWorld.room((6.0, 5.0), [(2.8, 1.5, 3.2, 3.5)])
    runs = [run(cls(), world, (1.0, 2.5, 0.0), (5.0, 2.5), time_s=15.0, seed=11,
                noise_std=0.02) for _ in range(2)]
    np.testing.assert_array_equal(runs[0].commands, runs[1].commands)
    assert runs[0].events == runs[1].events


def check_observation_is_not_modified(cls: type[Planner]) -> None:
    """``reset`` and ``act`` leave the observation's arrays as they were."""
    world, start, goal = open_room()
    robot = default_robot()
    obs = observe(world, np.array(start), np.array(goal), robot, 0.0, 0.1)
    pose, ranges, goal_xy = obs.pose.copy(), obs.ranges.copy(), obs.goal.copy()
    planner = cls()
    planner.reset(obs, np.random.default_rng(0))
    planner.act(obs)
    np.testing.assert_array_equal(obs.pose, pose)
    np.testing.assert_array_equal(obs.ranges, ranges)
    np.testing.assert_array_equal(obs.goal, goal_xy)


CHECKS = (check_declares_its_parameters, check_commands_are_bounded,
          check_reaches_the_goal_in_an_open_room, check_reset_forgets_the_previous_episode,
          check_same_seed_same_commands, check_observation_is_not_modified)


def check_planner(cls: type[Planner]) -> None:
    """Every check of :data:`CHECKS` on ``cls``; the first that fails raises."""
    for check in CHECKS:
        check(cls)
