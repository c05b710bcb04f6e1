"""Pure functions from an episode's trace to the numbers of its result row."""

from __future__ import annotations

import hashlib
import json
from functools import lru_cache
from typing import Any

import numpy as np

from nav_bench.specs import Mover, WorldSpec
from nav_bench.world.geometry import StaticGeometry, clearance, static_geometry


def stable_id(*parts: Any, length: int = 10) -> str:
    """Short hash of JSON-able ``parts``, stable across runs, machines and Python versions."""
    text = json.dumps(parts, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha1(text.encode()).hexdigest()[:length]


def spl(success: bool, optimal_m: float | None, travelled_m: float) -> float:
    """Success weighted by path length (Anderson et al. 2018): S * l / max(l, p)."""
    if not success or optimal_m is None:
        return 0.0
    return float(optimal_m / max(optimal_m, travelled_m, 1e-9))


def mover_radius(mover: Mover) -> float:
    """Radius of the disc that bounds a mover's footprint (m)."""
    if mover.shape.cylinder is not None:
        return mover.shape.cylinder.radius
    sx, sy = mover.shape.box.size
    return float(np.hypot(sx, sy) / 2)


def footprint_clearance(geometry: StaticGeometry, xy: np.ndarray, robot_radius: float,
                        mover_radii: np.ndarray | None = None,
                        mover_xy: np.ndarray | None = None) -> np.ndarray:
    """(T,) gap (m) between the robot's footprint disc at each of (T, 2) positions and the
    nearest obstacle; negative means overlap.

    Static geometry is exact; movers (``mover_radii`` (M,) m, ``mover_xy`` (T, M, 2) m) count
    by their bounding discs (:func:`mover_radius`), so a box mover's gap is slightly small.
    """
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    gaps = clearance(geometry, xy)
    if mover_xy is not None and mover_radii is not None and len(mover_radii):
        d = np.linalg.norm(np.asarray(mover_xy, dtype=float) - xy[:, None, :], axis=2)
        gaps = np.minimum(gaps, (d - mover_radii[None, :]).min(axis=1))
    return gaps - robot_radius


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
    from nav_bench.optimal import optimal_path

    world = WorldSpec.model_validate_json(world_json)
    return optimal_path(world, robot_radius).length_m


def optimal_length(world: WorldSpec, robot_radius: float) -> float | None:
    """Shortest collision-free path length (m) for a disc robot on the true static map.

    Memoised per process: a batch plays the same world many times.
    """
    return _optimal_cached(world.model_dump_json(by_alias=True), round(float(robot_radius), 6))
