"""A learned policy as a planner, and the observation and action a policy sees.

A policy maps a flat float32 vector (:func:`observation_vector`) to an action in ``[-1, 1]^2``
(:func:`command_of`): the same vector the Gymnasium environment (:mod:`nav_bench.gym`) gives
and the same scaling it applies, so a policy trained there drives the same robot here, and a
suite benchmarks it beside EO/PC and the baselines (same rows, same reports).

The observation (all from what a planner sees; SI units):

=========  ====  ==========================================================================
slice      size  meaning
=========  ====  ==========================================================================
ranges     K     sonar readings, m, in the robot's sonar order; ``max_range``: no echo
goal       2     the goal in the robot's odometry frame (x forward, y left), m
last_cmd   2     the command of the previous cycle: v (m/s), omega (rad/s); zeros at first
=========  ====  ==========================================================================

The action: ``(a_v, a_omega)`` in ``[-1, 1]``, clipped, then ``v = a_v * v_max`` and
``omega = a_omega * omega_max`` of the robot.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from nav_bench.errors import InputError
from nav_bench.interface import Command, Observation, RobotInfo
from nav_bench.planners.base import Param, Planner

Policy = Callable[[np.ndarray], Any]


def observation_vector(obs: Observation, last_cmd: Command) -> np.ndarray:
    """The policy's input: ``[ranges (K), goal in the odometry frame (2), last v, omega]``."""
    x, y, yaw = (float(v) for v in obs.pose)
    dx, dy = float(obs.goal[0]) - x, float(obs.goal[1]) - y
    c, s = math.cos(yaw), math.sin(yaw)
    goal = (c * dx + s * dy, -s * dx + c * dy)
    return np.concatenate([np.asarray(obs.ranges, dtype=np.float64), goal,
                           (last_cmd.v, last_cmd.omega)]).astype(np.float32)


def command_of(action: Any, robot: RobotInfo) -> Command:
    """The command of an action in ``[-1, 1]^2`` (clipped), scaled by the robot's limits.

    The action is taken as float32 first (the action space's type), so a policy's float64
    output drives the robot the same through the environment and through a planner."""
    a = np.asarray(action, dtype=np.float32).astype(np.float64).reshape(-1)
    if a.shape != (2,) or not np.all(np.isfinite(a)):
        raise InputError(f"a policy action is two finite numbers (v, omega) in [-1, 1], got {action!r}")
    a = np.clip(a, -1.0, 1.0)
    return Command(float(a[0]) * robot.v_max, float(a[1]) * robot.omega_max)


class LinearPolicy:
    """``action = tanh(W @ features(obs) + b)``: the small policy of ``examples/train_cem.py``.

    Features (:meth:`features`): sonar readings divided by ``range_scale`` (clipped to 1), the
    goal's bearing as cos and sin, its distance divided by ``goal_scale`` (clipped to 1), the
    last command divided by ``v_scale`` and ``omega_scale``. A ``.npz`` holds ``W`` (2, F),
    ``b`` (2,) and the four scales.
    """

    def __init__(self, W: np.ndarray, b: np.ndarray, *, range_scale: float = 3.0,
                 goal_scale: float = 5.0, v_scale: float = 0.75, omega_scale: float = 4.0) -> None:
        self.W = np.asarray(W, dtype=np.float64)
        self.b = np.asarray(b, dtype=np.float64).reshape(2)
        self.scales = dict(range_scale=float(range_scale), goal_scale=float(goal_scale),
                           v_scale=float(v_scale), omega_scale=float(omega_scale))
        if self.W.ndim != 2 or self.W.shape[0] != 2:
            raise InputError(f"linear policy: W must have shape (2, F), got {self.W.shape}")

    @staticmethod
    def n_features(n_sonars: int) -> int:
        return n_sonars + 5

    @classmethod
    def steer_to_goal(cls, n_sonars: int = 6) -> LinearPolicy:
        """Blind to the sonars: drive forward while the goal is ahead, turn toward it.
        The starting point of the cross-entropy example and the planner's default."""
        W = np.zeros((2, cls.n_features(n_sonars)))
        W[0, n_sonars], W[1, n_sonars + 1] = 1.5, 3.0  # v <- cos(bearing), omega <- sin(bearing)
        return cls(W, np.zeros(2))

    def features(self, vec: np.ndarray) -> np.ndarray:
        vec = np.asarray(vec, dtype=np.float64)
        ranges, (gx, gy), (v, w) = vec[:-4], vec[-4:-2], vec[-2:]
        sc = self.scales
        dist = math.hypot(gx, gy)
        bearing = math.atan2(gy, gx)
        return np.concatenate([np.minimum(ranges / sc["range_scale"], 1.0),
                               (math.cos(bearing), math.sin(bearing),
                                min(dist / sc["goal_scale"], 1.0),
                                v / sc["v_scale"], w / sc["omega_scale"])])

    def __call__(self, vec: np.ndarray) -> np.ndarray:
        phi = self.features(vec)
        if phi.shape[0] != self.W.shape[1]:
            raise InputError(f"linear policy: W has {self.W.shape[1]} columns, the robot gives "
                             f"{phi.shape[0]} features ({phi.shape[0] - 5} sonars)")
        return np.tanh(self.W @ phi + self.b)

    def save(self, path: str | Path) -> Path:
        path = Path(path)
        with path.open("wb") as fh:
            np.savez(fh, W=self.W, b=self.b, **{k: np.float64(v) for k, v in self.scales.items()})
        return path

    @classmethod
    def load(cls, path: str | Path) -> LinearPolicy:
        try:
            with np.load(path, allow_pickle=False) as data:
                scales = {k: float(data[k]) for k in ("range_scale", "goal_scale", "v_scale",
                                                       "omega_scale") if k in data.files}
                return cls(data["W"], data["b"], **scales)
        except (OSError, KeyError, ValueError) as exc:
            raise InputError(f"cannot read a linear policy from {str(path)!r} ({exc}); expected "
                             f"a .npz with W (2, F) and b (2,)") from None


class PolicyPlanner(Planner):
    """A policy ``obs vector -> action in [-1, 1]^2`` as a planner (see the module's doc).

    In code: ``PolicyPlanner(policy=any_callable)``. By name in a suite or on the command line:
    ``policy:weights=my_policy.npz`` (a :class:`LinearPolicy`) or
    ``policy:callable=mypkg.module:make_policy`` (a function returning the callable).
    """

    name = "policy"
    reference = "nav_bench.gym: a policy trained in the Gymnasium environment"
    params = (
        Param("weights", "", "-", ".npz of a linear policy (W, b; see LinearPolicy)"),
        Param("callable", "", "-", "module:function returning a policy (called once, no "
                                   "arguments); used when weights is empty. Neither: "
                                   "LinearPolicy.steer_to_goal, blind to the sonars"),
    )

    def __init__(self, policy: Policy | None = None, **overrides: Any) -> None:
        super().__init__(**overrides)
        self._policy = policy
        self._default = False
        self._last = Command(0.0, 0.0)

    def policy(self, n_sonars: int = 6) -> Policy:
        """The wrapped callable: given in code, else loaded from ``weights`` or ``callable``,
        else :meth:`LinearPolicy.steer_to_goal`."""
        if self._policy is None:
            if self.p["weights"]:
                from nav_bench.paths import project_file

                path = Path(self.p["weights"])
                self._policy = LinearPolicy.load(path if path.exists() else project_file(path))
            elif self.p["callable"]:
                from nav_bench.planners.registry import load_dotted

                self._policy = load_dotted(self.p["callable"])()
            else:
                self._policy, self._default = LinearPolicy.steer_to_goal(n_sonars), True
        return self._policy

    def reset(self, obs: Observation, rng: np.random.Generator) -> None:
        super().reset(obs, rng)
        if self._default:  # made for the sonars of the previous robot
            self._policy = None
        self.policy(len(obs.ranges))
        self._last = Command(0.0, 0.0)

    def act(self, obs: Observation) -> Command:
        action = self.policy(len(obs.ranges))(observation_vector(obs, self._last))
        self._last = command_of(action, obs.robot)
        return self._last
