"""The Gymnasium environment: the API, determinism, and one loop shared with the benchmark."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import nav_bench.gym  # noqa: E402, F401  (registers the ids)
from nav_bench.cli import main  # noqa: E402
from nav_bench.episode.row import WALL_CLOCK_FIELDS  # noqa: E402
from nav_bench.errors import InputError  # noqa: E402
from nav_bench.gym import SonarNavEnv  # noqa: E402
from nav_bench.interface import Command  # noqa: E402
from nav_bench.planners.policy import LinearPolicy, PolicyPlanner, command_of  # noqa: E402

SHORT = {"time_s": 6.0}


def rollout(env, policy, seed, steps=None):
    obs, _ = env.reset(seed=seed)
    observations, rewards = [obs], []
    info = {}
    for _ in range(steps or 10**6):
        obs, reward, terminated, truncated, info = env.step(np.float32(policy(obs)))
        observations.append(obs)
        rewards.append(reward)
        if terminated or truncated:
            break
    return np.array(observations), np.array(rewards), info


@pytest.mark.parametrize("observation", ["box", "dict"])
def test_env_checker_passes(observation):
    from gymnasium.utils.env_checker import check_env

    env = gymnasium.make("nav_bench/SonarNav-v0", world="paper/open_room", limits=SHORT,
                         observation=observation, render_mode="rgb_array")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any checker warning fails the test
        check_env(env.unwrapped)
    env.close()


def test_spaces_are_what_a_planner_sees():
    env = SonarNavEnv(world="paper/open_room", limits=SHORT)
    assert env.observation_space.shape == (10,) and env.observation_space.dtype == np.float32
    assert env.action_space.shape == (2,) and env.action_space.dtype == np.float32
    assert np.all(env.action_space.low == -1) and np.all(env.action_space.high == 1)
    obs, _ = env.reset(seed=0)
    # open_room: start (1, 1) facing the goal (9, 9): the goal is straight ahead, 8*sqrt(2) m
    assert obs[6] == pytest.approx(8 * 2**0.5, abs=0.02) and abs(obs[7]) < 0.02
    assert np.all(obs[:6] <= 3.0) and np.all(obs[8:] == 0.0)
    obs, *_ = env.step(np.array([1.0, -0.5], np.float32))
    assert obs[8] == pytest.approx(env.robot_info.v_max)  # the last command, in m/s and rad/s
    assert obs[9] == pytest.approx(-0.5 * env.robot_info.omega_max)
    env.close()


def test_same_seed_same_rollout_and_a_row_at_the_end():
    env = SonarNavEnv(world={"generate": "clutter", "seeds": "0..9", "set": {"size": [6, 6]}},
                      limits=SHORT)
    policy = LinearPolicy.steer_to_goal()
    obs_a, rew_a, info_a = rollout(env, policy, seed=7)
    obs_b, rew_b, info_b = rollout(env, policy, seed=7)
    np.testing.assert_array_equal(obs_a, obs_b)
    np.testing.assert_array_equal(rew_a, rew_b)
    assert info_a["row"]["world"] == info_b["row"]["world"]
    assert info_a["row"]["world"].startswith("clutter_")
    assert info_a["outcome"] == "timeout" and info_a["row"]["time_s"] == pytest.approx(6.0)
    assert len(rew_a) == 60  # 6 s at 10 Hz; truncated
    obs_c, _, _ = rollout(env, policy, seed=8)
    assert not np.array_equal(obs_a[:5], obs_c[:5])
    env.close()


def test_terminated_on_the_goal_with_the_goal_reward():
    env = SonarNavEnv(world="paper/open_room", reward={"goal": 100.0, "time": 0.0})
    _, rewards, info = rollout(env, LinearPolicy.steer_to_goal(), seed=1)
    assert info["outcome"] == "reached" and info["row"]["success"] is True
    # progress adds up to start-goal distance minus the tolerance; then the goal bonus
    assert rewards.sum() == pytest.approx(100.0 + 8 * 2**0.5 - info["row"]["goal_distance_m"],
                                          abs=1e-6)
    with pytest.raises(InputError, match="reset"):
        env.step(np.zeros(2, np.float32))
    env.close()


def test_rgb_array_frame():
    env = SonarNavEnv(world="paper/long_wall", limits=SHORT, render_mode="rgb_array", frame_px=200)
    env.reset(seed=0)
    for _ in range(5):
        env.step(np.array([1.0, 0.0], np.float32))
    frame = env.render()
    assert frame.shape == (200, 200, 3) and frame.dtype == np.uint8
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 4  # world, robot, cones, trail
    env.close()


def test_async_vector_env_runs_two():
    from gymnasium.vector import AsyncVectorEnv

    envs = AsyncVectorEnv([lambda: gymnasium.make("nav_bench/SonarNav-v0", limits=SHORT)] * 2)
    obs, _ = envs.reset(seed=[0, 1])
    assert obs.shape == (2, 10) and obs.dtype == np.float32
    for _ in range(5):
        obs, rewards, terminated, _, _ = envs.step(np.tile([0.5, 0.1], (2, 1)).astype(np.float32))
    assert obs.shape == (2, 10) and rewards.shape == (2,) and not terminated.any()
    envs.close()


@pytest.mark.slow
def test_the_env_and_nav_bench_episode_give_the_same_row(tmp_path, capsys):
    weights = tmp_path / "p.npz"
    rng = np.random.default_rng(0)
    policy = LinearPolicy(LinearPolicy.steer_to_goal().W + 0.3 * rng.normal(size=(2, 11)),
                          np.array([0.2, 0.0]))
    policy.save(weights)
    env = SonarNavEnv(world="paper/congested", planner="policy",
                      planner_params={"weights": str(weights)}, limits={"time_s": 40})
    _, _, info = rollout(env, LinearPolicy.load(weights), seed=4)
    env.close()
    assert main(["episode", "paper/congested", "--planner", f"policy:weights={weights}",
                 "--seed", "4", "--time-limit", "40", "--json"]) == 0
    row = json.loads(capsys.readouterr().out)
    stepped = dict(info["row"])
    for r in (row, stepped):  # wall-clock figures: the env does not time an outside policy
        for name in WALL_CLOCK_FIELDS:
            r.pop(name, None)
    assert stepped == row
    # it drove somewhere. The weights' path (a new tmp_path each run) is a parameter, so it is in
    # the episode's seed: the noise, and the path (2.9-5.4 m seen), differ from run to run
    assert row["path_length_m"] > 1.5


def test_policy_planner_in_code_and_its_action_scaling():
    planner = PolicyPlanner(policy=lambda obs: np.array([2.0, -0.25]))
    from nav_bench.testing.harness import default_robot, observe, open_room

    robot = default_robot(v_max=0.5, omega_max=2.0)
    world, start, goal = open_room()
    obs = observe(world, np.array(start), np.array(goal), robot, 0.0, 0.1)
    planner.reset(obs, np.random.default_rng(0))
    assert planner.act(obs) == Command(0.5, -0.5)  # clipped to 1, scaled by the limits
    with pytest.raises(InputError, match="two finite numbers"):
        command_of([np.nan, 0.0], robot)


def test_linear_policy_round_trip(tmp_path):
    policy = LinearPolicy(np.arange(22.0).reshape(2, 11) / 50, np.array([0.1, -0.1]),
                          goal_scale=4.0)
    again = LinearPolicy.load(policy.save(tmp_path / "w.npz"))
    vec = np.array([1, 2, 3, 3, 2, 1, 4.0, -1.0, 0.3, 0.2], np.float32)
    np.testing.assert_array_equal(policy(vec), again(vec))
    assert again.scales["goal_scale"] == 4.0
    with pytest.raises(InputError, match="W has 11 columns"):
        again(np.zeros(12, np.float32))
