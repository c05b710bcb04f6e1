"""Pure functions from an episode's trace to the numbers of its result row."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from nav_bench.specs import WorldSpec
from nav_bench.world.geometry import footprint_clearance, mover_radius, static_geometry
from nav_bench.world.optimal import optimal_path


def spl(success: bool, optimal_m: float | None, travelled_m: float) -> float:
    """Success weighted by path length (Anderson et al. 2018): S * l / max(l, p)."""
    if not success or optimal_m is None:
        return 0.0
    return float(optimal_m / max(optimal_m, travelled_m, 1e-9))


def min_clearance(world: WorldSpec, xy: np.ndarray, robot_radius: float,
                  mover_xy: np.ndarray | None = None) -> float:
    """Smallest gap (m) between the robot's edge and true geometry along (T, 2) positions
    (:func:`footprint_clearance`; movers at ``mover_xy`` (T, M, 2)). Negative means overlap."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    if len(xy) == 0:
        return float("nan")
    radii = np.array([mover_radius(m) for m in world.movers], dtype=float)
    return float(footprint_clearance(static_geometry(world), xy, robot_radius, radii,
                                     mover_xy).min())


@lru_cache(maxsize=64)
def _optimal_cached(world_json: str, robot_radius: float) -> float | None:
    world = WorldSpec.model_validate_json(world_json)
    return optimal_path(world, robot_radius).length_m


def optimal_length(world: WorldSpec, robot_radius: float) -> float | None:
    """Shortest collision-free path length (m) for a disc robot on the true static map.

    Memoised per process: a batch plays the same world many times.
    """
    return _optimal_cached(world.model_dump_json(by_alias=True), round(float(robot_radius), 6))
