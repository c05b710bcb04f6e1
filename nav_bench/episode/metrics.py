"""Pure functions from an episode's trace to the numbers of its result row."""

from __future__ import annotations

from collections.abc import Mapping
from functools import lru_cache
from typing import Any

import numpy as np

from nav_bench.interface import GridState
from nav_bench.mapping.quality import MapQuality, map_quality, true_occupancy
from nav_bench.specs import WorldSpec
from nav_bench.world.geometry import footprint_clearance, mover_radius, static_geometry
from nav_bench.world.optimal import OptimalPath, optimal_path


def spl(success: bool, optimal_m: float | None, travelled_m: float) -> float:
    """Success weighted by path length (Anderson et al. 2018): S * l / max(l, p)."""
    if not success or optimal_m is None:
        return 0.0
    return float(optimal_m / max(optimal_m, travelled_m, 1e-9))


def clearances(world: WorldSpec, xy: np.ndarray, robot_radius: float,
               mover_xy: np.ndarray | None = None) -> np.ndarray:
    """(T,) gap (m) between the robot's edge and true geometry at each of (T, 2) positions
    (:func:`footprint_clearance`; movers at ``mover_xy`` (T, M, 2)). Negative means overlap."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    if len(xy) == 0:
        return np.zeros(0)
    radii = np.array([mover_radius(m) for m in world.movers], dtype=float)
    return np.asarray(footprint_clearance(static_geometry(world), xy, robot_radius, radii, mover_xy),
                      dtype=float)


def min_clearance(world: WorldSpec, xy: np.ndarray, robot_radius: float,
                  mover_xy: np.ndarray | None = None) -> float:
    """Smallest of :func:`clearances` (m); NaN without positions."""
    gaps = clearances(world, xy, robot_radius, mover_xy)
    return float(gaps.min()) if len(gaps) else float("nan")


@lru_cache(maxsize=64)
def _optimal_cached(world_json: str, robot_radius: float) -> OptimalPath:
    world = WorldSpec.model_validate_json(world_json)
    return optimal_path(world, robot_radius)


def optimal_route(world: WorldSpec, robot_radius: float) -> OptimalPath:
    """Shortest collision-free path (:func:`optimal_path`) for a disc robot on the true static map.

    Memoised per process: a batch plays the same world many times, and the row asks for both
    its length and (for the map quality) its cells.
    """
    return _optimal_cached(world.model_dump_json(by_alias=True), round(float(robot_radius), 6))


def optimal_length(world: WorldSpec, robot_radius: float) -> float | None:
    """Shortest collision-free path length (m) for a disc robot on the true static map."""
    return optimal_route(world, robot_radius).length_m


def planner_map_quality(world: WorldSpec, planner_state: Mapping[str, Any] | None,
                        robot_radius: float) -> MapQuality | None:
    """The planner's final grid (its ``debug_state()``, :class:`GridState`) against the true
    static map (:func:`nav_bench.mapping.quality.map_quality`); None when it keeps no grid."""
    grids = GridState.from_state(planner_state)
    if grids is None or np.asarray(grids.pmo).ndim != 2:
        return None
    truth = true_occupancy(static_geometry(world), grids)
    route = optimal_route(world, robot_radius)
    return map_quality(grids, truth, route.points if route.length_m is not None else None)
