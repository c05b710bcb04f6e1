"""What every registered planner must do, checked on all of them (kinematic harness).

A planner added to the registry (built in or through an entry point) is picked up here
without any change. Runtime: ~5 s for the seven built-in planners.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from harness import BoxWorld, default_robot, observe, open_room, run, u_world

from nav_bench.interface import Command, Observation
from nav_bench.planners.base import Param, Planner, resolve_params
from nav_bench.planners.registry import default_registry, load_planner_set

NAMES = default_registry().names()
CONFIGS = Path(__file__).resolve().parents[2] / "configs" / "planners"
BASELINES = ("bug2", "tangent_bug", "dstar_lite", "vfh_plus", "apf", "dwa", "dwa_global")


def planner_class(name: str) -> type[Planner]:
    return default_registry().get(name)


@pytest.mark.parametrize("name", NAMES)
def test_declares_its_parameters(name: str) -> None:
    cls = planner_class(name)
    assert cls.name == name
    names = [p.name for p in cls.params]
    assert len(names) == len(set(names)), "parameter names must be unique"
    for p in cls.params:
        assert isinstance(p, Param)
        assert isinstance(p.unit, str) and p.unit.strip(), f"{p.name}: no unit"
        assert isinstance(p.doc, str) and len(p.doc.strip()) > 5, f"{p.name}: no doc"
        assert p.check(p.default) == p.default, f"{p.name}: default fails its own check"
    assert resolve_params(cls, {}) == {p.name: p.default for p in cls.params}


def random_observation(rng: np.random.Generator, robot, t: float) -> Observation:
    s = robot.sonar
    ranges = rng.uniform(s.min_range, s.max_range, len(s.angles))
    ranges[rng.random(len(ranges)) < 0.3] = s.max_range  # some "no echo"
    ranges[rng.random(len(ranges)) < 0.1] = s.min_range  # some touching
    pose = np.array([rng.uniform(0.5, 5.5), rng.uniform(0.5, 4.5), rng.uniform(-math.pi, math.pi)])
    return Observation(t=t, pose=pose, goal=np.array([rng.uniform(0.5, 5.5), rng.uniform(0.5, 4.5)]),
                       ranges=ranges, robot=robot, bounds=(0.0, 0.0, 6.0, 5.0), dt=0.1)


@pytest.mark.parametrize("limits", [(0.5, 2.0), (0.15, 0.4)], ids=["diffbot", "slow_robot"])
@pytest.mark.parametrize("name", NAMES)
def test_commands_are_finite_and_within_the_robot_limits(name: str, limits: tuple[float, float]) -> None:
    robot = default_robot(v_max=limits[0], omega_max=limits[1])
    rng = np.random.default_rng(3)
    planner = planner_class(name)()
    planner.reset(random_observation(rng, robot, 0.0), np.random.default_rng(0))
    for i in range(1, 150):  # nonsense sensing: jumps, touching readings, random goals
        cmd = planner.act(random_observation(rng, robot, 0.1 * i))
        assert isinstance(cmd, Command)
        assert math.isfinite(cmd.v) and math.isfinite(cmd.omega)
        assert abs(cmd.v) <= robot.v_max + 1e-9
        assert abs(cmd.omega) <= robot.omega_max + 1e-9
    assert isinstance(planner.debug_state(), dict)


@pytest.mark.parametrize("name", NAMES)
def test_reaches_the_goal_in_an_open_room(name: str) -> None:
    world, start, goal = open_room()
    result = run(planner_class(name)(), world, start, goal, time_s=60.0)
    assert result.reached, f"{name} ended {math.dist(result.poses[-1, :2], goal):.2f} m from the goal"
    assert result.collisions == 0
    assert result.path_length < 2.0 * math.dist(start[:2], goal)


@pytest.mark.parametrize("name", NAMES)
def test_reset_forgets_the_previous_episode(name: str) -> None:
    cls = planner_class(name)
    world, start, goal = open_room()
    used = cls()
    assert isinstance(used.debug_state(), dict)  # callable before the first reset
    u, u_start, u_goal = u_world()
    run(used, u, u_start, u_goal, time_s=15.0, seed=5, noise_std=0.02)  # leave state behind
    again = run(used, world, start, goal, time_s=20.0, seed=1, noise_std=0.01)
    fresh = run(cls(), world, start, goal, time_s=20.0, seed=1, noise_std=0.01)
    np.testing.assert_array_equal(again.commands, fresh.commands)
    assert again.events == fresh.events


@pytest.mark.parametrize("name", NAMES)
def test_same_seed_same_commands(name: str) -> None:
    world = BoxWorld.room((6.0, 5.0), [(2.8, 1.5, 3.2, 3.5)])
    runs = [run(planner_class(name)(), world, (1.0, 2.5, 0.0), (5.0, 2.5), time_s=15.0, seed=11,
                noise_std=0.02) for _ in range(2)]
    np.testing.assert_array_equal(runs[0].commands, runs[1].commands)
    assert runs[0].events == runs[1].events


@pytest.mark.parametrize("name", NAMES)
def test_observation_is_not_modified(name: str) -> None:
    world, start, goal = open_room()
    robot = default_robot()
    obs = observe(world, np.array(start), np.array(goal), robot, 0.0, 0.1)
    pose, ranges, goal_xy = obs.pose.copy(), obs.ranges.copy(), obs.goal.copy()
    planner = planner_class(name)()
    planner.reset(obs, np.random.default_rng(0))
    planner.act(obs)
    np.testing.assert_array_equal(obs.pose, pose)
    np.testing.assert_array_equal(obs.ranges, ranges)
    np.testing.assert_array_equal(obs.goal, goal_xy)


@pytest.mark.parametrize("name", BASELINES)
def test_shipped_parameter_set_is_valid_and_spells_out_the_defaults(name: str) -> None:
    spec = load_planner_set(CONFIGS / f"{name}.yaml")
    assert spec.planner == name
    cls = planner_class(name)
    assert spec.params == {p.name: p.default for p in cls.params}
    assert cls.reference and cls.__module__.startswith("nav_bench.planners.")
    assert cls.reference.split(",")[0].split()[0] in (cls.__doc__ or "")  # first author in the doc
