"""How hard is a world? The five BARN difficulty measures along the optimal path.

Perille, Truong, Xiao, Stone, "Benchmarking Metric Ground Navigation" (SSRR 2020) rate a
map by five measures, each averaged over the cells of the shortest path from start to
goal. Here they are computed in continuous space (metres) on the true geometry, along the
disc robot's optimal path (:func:`nav_bench.world.optimal.optimal_path`) sampled every
``resolution`` m of arc length, so that a sample stands for an equal length of path:

``closest_obstacle_m``
    mean distance from the path to the nearest obstacle surface (m). Exact (the primitives'
    signed distance). A straight corridor of width w gives w / 2.
``average_visibility_m``
    mean, over the path, of the mean free length of 8 rays (every 45 deg) cast until they
    hit an obstacle (m). Large in open space, small in clutter.
``dispersion``
    mean, over the path, of the number of alternations between blocked and open rays among
    16 rays (every 22.5 deg) around the point, a ray being blocked when it hits an obstacle
    within ``dispersion_radius`` (count, even, >= 0). Many gaps around the robot, many
    alternations. BARN uses 3 cells of 0.15 m on its inflated (C-space) grid; the default
    here, ``robot_radius + 0.45`` m on the true geometry, is the same rule.
``characteristic_dimension_m``
    mean, over the path, of the narrowest chord through the point along 4 axes (0, 45, 90,
    135 deg): the free length to the nearest obstacle in both directions added (m).
    A straight corridor of width w gives w.
``tortuosity``
    optimal path length / straight-line distance start-goal (>= 1, dimensionless).

Differences from BARN, on purpose: rays and distances are exact (not counted in grid
steps), the 16 dispersion rays are equally spaced (BARN's in-between rays have slopes 1/2
and 2), and the measures use the obstacles themselves rather than the robot-inflated grid
(the path is the inflated-grid optimum, as in BARN). The world rectangle's edges count as
obstacles (they carry the boundary walls). Two more fields: ``free_area_m2``, the area of
the world not covered by obstacles, and ``optimal_length_m``. When the goal is unreachable
the path measures are ``None``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from nav_bench.specs import WorldSpec, default_robot_radius
from nav_bench.world.geometry import StaticGeometry, clearance, static_geometry
from nav_bench.world.optimal import optimal_path
from nav_bench.world.raster import rasterize

DISPERSION_MARGIN_M = 0.45  # BARN: 3 cells of 0.15 m beyond the inflated obstacles
MAX_SAMPLES = 4000


def sample_polyline(points: np.ndarray, step: float) -> np.ndarray:
    """Points (K, 2) every ``step`` m of arc length along a polyline (N, 2), ends included.

    The spacing is shrunk slightly so it divides the length exactly.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    seg = np.hypot(*np.diff(p, axis=0).T)
    total = float(seg.sum())
    if len(p) < 2 or total == 0.0:
        return p[:1].copy()
    n = max(2, math.ceil(total / step) + 1)
    s = np.linspace(0.0, total, n)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    x = np.interp(s, cum, p[:, 0])
    y = np.interp(s, cum, p[:, 1])
    return np.column_stack([x, y])


def cast_rays(geometry: StaticGeometry, origins: np.ndarray, angles: np.ndarray,
              chunk: int = 1 << 21) -> np.ndarray:
    """Free length (m) of rays from each origin in each direction, exact.

    A ray stops at the first box, cylinder or edge of the world rectangle
    ``[0, sx] x [0, sy]``; an origin inside an obstacle reads 0.

    Args:
        origins: (K, 2) m. angles: (D,) rad, CCW from +x.
    Returns:
        (K, D) m.
    """
    o = np.asarray(origins, dtype=float).reshape(-1, 2)
    ang = np.asarray(angles, dtype=float).ravel()
    ux, uy = np.cos(ang)[None, :], np.sin(ang)[None, :]  # (1, D)
    ox, oy = o[:, 0:1], o[:, 1:2]  # (K, 1)
    sx, sy = geometry.size
    with np.errstate(divide="ignore", invalid="ignore"):
        tx = np.where(ux > 1e-12, (sx - ox) / ux, np.where(ux < -1e-12, -ox / ux, np.inf))
        ty = np.where(uy > 1e-12, (sy - oy) / uy, np.where(uy < -1e-12, -oy / uy, np.inf))
    out = np.maximum(np.minimum(tx, ty), 0.0)  # (K, D)
    rays_o = np.broadcast_to(o[:, None, :], (len(o), len(ang), 2)).reshape(-1, 2)
    rays_u = np.broadcast_to(np.stack([ux, uy], -1), (len(o), len(ang), 2)).reshape(-1, 2)
    flat = out.reshape(-1)
    n_rays = len(flat)
    for prims, hit in ((geometry.boxes, _ray_boxes), (geometry.cylinders, _ray_cylinders)):
        if not len(prims) or not n_rays:
            continue
        step = max(1, chunk // len(prims))
        for i in range(0, n_rays, step):
            t = hit(rays_o[i:i + step], rays_u[i:i + step], prims)
            flat[i:i + step] = np.minimum(flat[i:i + step], t)
    return flat.reshape(len(o), len(ang))


def _ray_boxes(o: np.ndarray, u: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(R,) nearest hit distance of R rays against oriented boxes (N, 5) (inf: none)."""
    c, s = np.cos(b[:, 4])[None, :], np.sin(b[:, 4])[None, :]
    dx, dy = o[:, 0:1] - b[None, :, 0], o[:, 1:2] - b[None, :, 1]
    px, py = c * dx + s * dy, -s * dx + c * dy  # origin in the box frame (R, N)
    vx, vy = c * u[:, 0:1] + s * u[:, 1:2], -s * u[:, 0:1] + c * u[:, 1:2]
    t_near = np.full(px.shape, -np.inf)
    t_far = np.full(px.shape, np.inf)
    for p, v, half in ((px, vx, b[None, :, 2] / 2), (py, vy, b[None, :, 3] / 2)):
        parallel = np.abs(v) < 1e-12
        with np.errstate(divide="ignore", invalid="ignore"):
            t1, t2 = (-half - p) / v, (half - p) / v
        lo, hi = np.minimum(t1, t2), np.maximum(t1, t2)
        lo = np.where(parallel, np.where(np.abs(p) <= half, -np.inf, np.inf), lo)
        hi = np.where(parallel, np.where(np.abs(p) <= half, np.inf, -np.inf), hi)
        t_near, t_far = np.maximum(t_near, lo), np.minimum(t_far, hi)
    hit = (t_far >= t_near) & (t_far >= 0.0)
    return np.where(hit, np.maximum(t_near, 0.0), np.inf).min(axis=1)


def _ray_cylinders(o: np.ndarray, u: np.ndarray, cy: np.ndarray) -> np.ndarray:
    """(R,) nearest hit distance of R rays against circles (M, 3) (inf: none)."""
    dx, dy = o[:, 0:1] - cy[None, :, 0], o[:, 1:2] - cy[None, :, 1]
    bq = u[:, 0:1] * dx + u[:, 1:2] * dy
    cq = dx * dx + dy * dy - cy[None, :, 2] ** 2
    disc = bq * bq - cq
    root = np.sqrt(np.maximum(disc, 0.0))
    t = -bq - root
    t = np.where(cq <= 0.0, 0.0, np.where((disc >= 0.0) & (t >= 0.0), t, np.inf))
    return t.min(axis=1)


def path_measures(geometry: StaticGeometry, points: np.ndarray, dispersion_radius: float
                  ) -> dict[str, float]:
    """The four per-point BARN measures averaged over sample ``points`` (K, 2) m."""
    sx, sy = geometry.size
    edge = np.minimum.reduce([points[:, 0], sx - points[:, 0], points[:, 1], sy - points[:, 1]])
    closest = np.minimum(clearance(geometry, points), edge)
    rays = cast_rays(geometry, points, np.arange(16) * (2 * math.pi / 16))  # every 22.5 deg
    visibility = rays[:, ::2].mean(axis=1)  # the 8 rays every 45 deg
    blocked = rays <= dispersion_radius
    dispersion = (blocked != np.roll(blocked, -1, axis=1)).sum(axis=1)  # circular alternations
    chords = rays[:, 0:8:2] + rays[:, 8:16:2]  # 0/180, 45/225, 90/270, 135/315 deg
    return {
        "closest_obstacle_m": float(closest.mean()),
        "average_visibility_m": float(visibility.mean()),
        "dispersion": float(dispersion.mean()),
        "characteristic_dimension_m": float(chords.min(axis=1).mean()),
    }


def difficulty(world: WorldSpec, robot_radius: float | None = None, resolution: float = 0.05, *,
               dispersion_radius: float | None = None) -> dict[str, Any]:
    """BARN difficulty measures of a world for a disc robot (see the module docstring).

    Args:
        robot_radius: m, for the optimal path; default: the default robot's.
        resolution: m, raster cell of the optimal path and the free area, and the spacing of
            the path samples (grown if the path would need more than 4000 samples).
        dispersion_radius: m, default ``robot_radius + 0.45``.
    Returns:
        ``closest_obstacle_m``, ``average_visibility_m``, ``dispersion``,
        ``characteristic_dimension_m``, ``tortuosity``, ``free_area_m2``, ``optimal_length_m``
        (path measures ``None`` when the goal is unreachable).
    """
    robot_radius = default_robot_radius() if robot_radius is None else robot_radius
    geometry = static_geometry(world)
    free = ~rasterize(geometry, resolution).occupied
    out: dict[str, Any] = {"closest_obstacle_m": None, "average_visibility_m": None,
                           "dispersion": None, "characteristic_dimension_m": None,
                           "tortuosity": None,
                           "free_area_m2": float(free.sum() * resolution**2),
                           "optimal_length_m": None}
    path = optimal_path(world, robot_radius, resolution)
    if path.length_m is None:
        return out
    step = max(resolution, path.length_m / (MAX_SAMPLES - 1))
    samples = sample_polyline(path.points, step)
    radius = robot_radius + DISPERSION_MARGIN_M if dispersion_radius is None else dispersion_radius
    out.update(path_measures(geometry, samples, radius))
    chord = math.dist(world.start[:2], world.goal)
    out["tortuosity"] = path.length_m / chord if chord > 0 else 1.0
    out["optimal_length_m"] = path.length_m
    return out
