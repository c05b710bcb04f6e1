"""``nav_bench/SonarNav-v0``: a nav-bench episode in the Gymnasium API.

The environment drives the same :class:`~nav_bench.episode.stepper.EpisodeStepper` as the
benchmark's loop (:func:`~nav_bench.episode.loop.run_episode`): the same simulation, endings,
trace and result row. An episode stepped here with a policy and the same policy played by
``nav-bench episode --planner policy:...`` (:class:`~nav_bench.planners.policy.PolicyPlanner`)
give the same row, but for ``wall_s``.

Observation (``observation="box"``, float32): ``[ranges (K, m), goal in the robot's odometry
frame (x forward, y left, m), last command (v m/s, omega rad/s)]``, see
:func:`~nav_bench.planners.policy.observation_vector`; ``observation="dict"`` gives the three
parts under ``ranges``, ``goal`` and ``last_cmd``. Action: ``(v, omega)`` scaled to
``[-1, 1]`` (float32), times the robot's ``v_max`` and ``omega_max``.

Reward per control cycle, with weights from ``reward=`` (defaults in :data:`REWARD`):
``progress`` x metres the true distance to the goal shrank, ``goal`` once on reaching it,
``collision`` x new contacts, ``time`` x seconds. ``terminated`` when the goal is reached,
``truncated`` on the time limit, when stuck, or when the episode failed; the last ``info``
holds ``row`` (the result row, a dict) and ``outcome``.
"""

from __future__ import annotations

import math
import time
from typing import Any, ClassVar

import gymnasium
import numpy as np
from gymnasium import spaces

from nav_bench.episode.settings import EpisodeSettings
from nav_bench.episode.stepper import EpisodeStepper
from nav_bench.errors import InputError
from nav_bench.gym.worlds import world_pool
from nav_bench.interface import Command, Observation, Outcome, RobotInfo
from nav_bench.paths import find
from nav_bench.planners.policy import command_of, observation_vector
from nav_bench.sim.session import SimSession
from nav_bench.specs import PlannerSetSpec, RobotSpec, load_robot

REWARD: dict[str, float] = {
    "progress": 1.0,  # per metre the robot's true distance to the goal shrank
    "goal": 10.0,  # once, on reaching the goal
    "collision": -1.0,  # per new contact with anything but the floor
    "time": -0.1,  # per simulated second
}
GOAL_BOUND_M = 1000.0  # the goal's coordinates in the observation space's bounds


class SonarNavEnv(gymnasium.Env):
    """A nav-bench world, robot and limits as a Gymnasium environment.

    Args:
        world: a world file or shipped name (``paper/open_room``), a glob
            (``worlds/generated/*.yaml``), a generator family (``{"generate": "clutter",
            "seeds": "0..999", "set": {"density": 0.1}}``, one world per sampled seed), a
            :class:`WorldSpec`, or a list of these; each ``reset`` samples one.
        robot: a robot file or name (default ``diffbot``) or a :class:`RobotSpec`.
        limits: :class:`EpisodeSettings` fields (``time_s``, ``stuck_s``, ``goal_tolerance``,
            ``control_hz``...), as a suite's ``limits:``.
        reward: weights overriding :data:`REWARD`.
        observation: ``"box"`` (flat float32) or ``"dict"``.
        planner, planner_params: who the result row says played (default ``policy`` with its
            defaults, as ``nav-bench episode --planner policy``); they also seed the episode's
            generator, as in the benchmark.
        render_mode: ``"rgb_array"`` (a top-down frame) or ``"human"`` (a matplotlib window).
    """

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["rgb_array", "human"], "render_fps": 10}

    def __init__(self, world: Any = "paper/open_room", robot: str | RobotSpec | None = None,
                 limits: dict[str, Any] | None = None, reward: dict[str, float] | None = None,
                 observation: str = "box", planner: str = "policy",
                 planner_params: dict[str, Any] | None = None, render_mode: str | None = None,
                 frame_px: int = 480) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise InputError(f"render_mode must be one of {self.metadata['render_modes']}, "
                             f"got {render_mode!r}")
        if observation not in ("box", "dict"):
            raise InputError(f"observation must be 'box' or 'dict', got {observation!r}")
        unknown = set(reward or {}) - set(REWARD)
        if unknown:
            raise InputError(f"unknown reward weight(s) {sorted(unknown)}; known: {list(REWARD)}")
        self.render_mode, self.frame_px, self._obs_kind = render_mode, int(frame_px), observation
        self.reward_weights = {**REWARD, **(reward or {})}
        self.pool = world_pool(world)
        if isinstance(robot, RobotSpec):
            self.robot = robot
        else:
            self.robot = load_robot(find("robot", robot).path if robot else None)
        self.settings = EpisodeSettings(**(limits or {}))
        self.planner = PlannerSetSpec(planner=planner, params=dict(planner_params or {}))
        self.session = SimSession(gui=False, physics_hz=self.settings.physics_hz)
        self.session.open()
        self.robot_info = EpisodeStepper.robot_info_of(self.session, self.robot, self.settings)
        self.observation_space = _observation_space(self.robot_info, observation)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self.stepper: EpisodeStepper | None = None
        self.world_file: str | None = None
        self._last = Command(0.0, 0.0)
        self._obs: Observation | None = None
        self._dist = 0.0
        self._collisions = 0
        self._trail: list[tuple[float, float]] = []
        self._wall0 = 0.0
        self._figure: Any = None

    # -- the Gymnasium API ---------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[Any, dict[str, Any]]:
        """A new episode. ``seed`` seeds the world choice and is the episode's seed (as
        ``nav-bench episode --seed``); without one, both come from the environment's
        generator. ``options={"world": ...}`` plays that world instead of sampling."""
        super().reset(seed=seed)
        if options and "world" in options:
            world, self.world_file = world_pool(options["world"]).sample(self.np_random)
        else:
            world, self.world_file = self.pool.sample(self.np_random)
        episode_seed = seed if seed is not None else int(self.np_random.integers(2**31 - 1))
        self._wall0 = time.perf_counter()
        self.stepper = EpisodeStepper(self.session, world, self.planner, seed=episode_seed,
                                      robot=self.robot, settings=self.settings,
                                      world_file=self.world_file)
        self._last = Command(0.0, 0.0)
        self._obs = self.stepper.observe()
        if self._obs is None:  # ended before the first cycle (the start is at the goal, or broken)
            self._obs = self.stepper.final_observation()
        self._dist = self._goal_distance()
        self._collisions = 0
        self._trail = [tuple(self.stepper.true_pose()[:2])]
        info = {"world": world.name, "seed": episode_seed}
        if self.render_mode == "human":
            self.render()
        return self._observe(self._obs), info

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict[str, Any]]:
        stepper = self.stepper
        if stepper is None or stepper.done:
            raise InputError("step() after the episode ended: call reset() first")
        cmd = command_of(action, self.robot_info)
        stepper.advance(cmd)
        self._last = cmd
        obs = stepper.observe()
        self._trail.append(tuple(stepper.true_pose()[:2]))
        dist = self._goal_distance()
        collisions = stepper.collisions
        w = self.reward_weights
        reward = (w["progress"] * (self._dist - dist) + w["collision"] * (collisions - self._collisions)
                  + w["time"] * self.settings.cycle_s)
        self._dist, self._collisions = dist, collisions
        info: dict[str, Any] = {"t": stepper.t}
        terminated = truncated = False
        if obs is None:
            outcome = stepper.outcome
            terminated = outcome is Outcome.REACHED
            truncated = not terminated
            if terminated:
                reward += w["goal"]
            obs = stepper.final_observation()
            result = stepper.finish(wall_s=time.perf_counter() - self._wall0)
            info.update(outcome=str(outcome), row=result.row.to_json())
        self._obs = obs
        if self.render_mode == "human":
            self.render()
        return self._observe(obs), float(reward), terminated, truncated, info

    def render(self) -> np.ndarray | None:
        if self.render_mode is None or self.stepper is None or self._obs is None:
            return None
        from nav_bench.gym.render import draw_frame

        frame, self._figure = draw_frame(self._figure, self.stepper.world, self.robot_info,
                                         self.stepper.true_pose(), self._obs.ranges, self._trail,
                                         px=self.frame_px, show=self.render_mode == "human")
        return frame if self.render_mode == "rgb_array" else None

    def close(self) -> None:
        self.session.close()
        if self._figure is not None:
            import matplotlib.pyplot as plt

            plt.close(self._figure)
            self._figure = None

    # -- helpers -------------------------------------------------------------------------------
    def _goal_distance(self) -> float:
        assert self.stepper is not None
        x, y = self.stepper.true_pose()[:2]
        gx, gy = self.stepper.world.goal
        return math.hypot(gx - x, gy - y)

    def _observe(self, obs: Observation) -> Any:
        vec = observation_vector(obs, self._last)
        if self._obs_kind == "box":
            return vec
        k = len(obs.ranges)
        return {"ranges": vec[:k], "goal": vec[k:k + 2], "last_cmd": vec[k + 2:]}


def _observation_space(robot: RobotInfo, kind: str) -> spaces.Space:
    k = len(robot.sonar.angles)
    r = robot.sonar.max_range
    low = np.array([0.0] * k + [-GOAL_BOUND_M] * 2 + [-robot.v_max, -robot.omega_max], np.float32)
    high = np.array([r] * k + [GOAL_BOUND_M] * 2 + [robot.v_max, robot.omega_max], np.float32)
    if kind == "box":
        return spaces.Box(low, high, dtype=np.float32)
    return spaces.Dict({"ranges": spaces.Box(low[:k], high[:k], dtype=np.float32),
                        "goal": spaces.Box(low[k:k + 2], high[k:k + 2], dtype=np.float32),
                        "last_cmd": spaces.Box(low[k + 2:], high[k + 2:], dtype=np.float32)})
