"""Stable ids and per-episode random generators.

An id is a short hash of JSON-able parts, the same on every machine and Python version; an
episode's generator derives from the ids of what it plays, so any episode of a batch can be
replayed alone.
"""

from __future__ import annotations

import hashlib
import json
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from nav_bench.specs import RobotSpec


def stable_id(*parts: Any, length: int = 10) -> str:
    """Short hash of JSON-able ``parts``, stable across runs, machines and Python versions."""
    text = json.dumps(parts, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha1(text.encode()).hexdigest()[:length]


def params_id(planner: str, params: dict[str, Any]) -> str:
    """Short stable hash of a planner name and its full parameter set."""
    return stable_id(planner, params)


def robot_id(robot: RobotSpec) -> str:
    """Short stable hash of everything that defines the robot (URDF contents included)."""
    dump = robot.model_dump(mode="json", exclude={"base_dir", "name"})
    try:
        urdf_digest = stable_id(robot.urdf_path.read_text(encoding="utf-8"), length=16)
    except OSError:
        urdf_digest = None
    return stable_id(dump, urdf_digest)


def episode_rng(world_name: str, pid: str, rid: str, seed: int) -> np.random.Generator:
    """The episode's one random generator, derived from what identifies the episode.

    The same (world, parameter set, robot, seed) gives the same stream on any machine, so any
    episode of a batch can be replayed alone.
    """
    words = [int(stable_id(world_name, pid, rid, length=16), 16) & 0xFFFFFFFF, int(seed)]
    return np.random.default_rng(np.random.SeedSequence(words))
