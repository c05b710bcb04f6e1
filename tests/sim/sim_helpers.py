"""Helpers shared by the simulator tests (imported as ``sim_helpers``)."""

from __future__ import annotations

from typing import Any

import numpy as np

from nav_bench.sim import SimSession, Simulation
from nav_bench.specs import RobotSpec, WorldSpec


def make_world(start: tuple[float, float, float] = (2.0, 5.0, 0.0),
               obstacles: list[dict[str, Any]] | None = None, *, size=(10.0, 10.0),
               boundary: bool = False, **extra: Any) -> WorldSpec:
    """A world spec built in code; ``start`` yaw in degrees as in YAML."""
    return WorldSpec.model_validate({
        "name": "test", "size": list(size), "boundary": boundary, "start": list(start),
        "goal": [size[0] - 1.0, size[1] - 1.0], "obstacles": obstacles or [], **extra})


def make_sim(session: SimSession, world: WorldSpec, robot: RobotSpec, seed: int = 0) -> Simulation:
    return Simulation(session, world, robot, np.random.default_rng(seed))
