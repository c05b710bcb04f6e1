"""nav-bench as a Gymnasium environment (``pip install "nav-bench[gym]"``).

Importing this package registers ``nav_bench/SonarNav-v0``::

    import gymnasium
    import nav_bench.gym  # noqa: F401  (registers the ids)

    env = gymnasium.make("nav_bench/SonarNav-v0", world={"generate": "clutter", "seeds": "0..99"},
                         limits={"time_s": 60}, reward={"collision": -2.0})

or without the import: ``gymnasium.make("nav_bench.gym:nav_bench/SonarNav-v0", ...)``.
See :class:`~nav_bench.gym.env.SonarNavEnv` for every keyword, and
:class:`~nav_bench.planners.policy.PolicyPlanner` for benchmarking a trained policy.
"""

from __future__ import annotations

try:
    import gymnasium
except ImportError as exc:  # pragma: no cover - depends on the installed extras
    from nav_bench.errors import InputError

    raise InputError('nav_bench.gym needs gymnasium: pip install "nav-bench[gym]"') from exc

from nav_bench.gym.env import REWARD, SonarNavEnv

ENV_IDS = ("nav_bench/SonarNav-v0",)

if "nav_bench/SonarNav-v0" not in gymnasium.registry:
    gymnasium.register(id="nav_bench/SonarNav-v0", entry_point="nav_bench.gym.env:SonarNavEnv",
                       max_episode_steps=None)

__all__ = ["ENV_IDS", "REWARD", "SonarNavEnv"]
