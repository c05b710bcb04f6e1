"""A tiny ray-cast sonar over axis-aligned boxes, for testing the sensor model without PyBullet.

Same reading rule as ``nav_bench.sim.sonar``: the nearest hit over rays evenly spread across
the cone (edges included), ``max_range`` when no ray hits.
"""

from __future__ import annotations

import math

import numpy as np

from nav_bench.interface import SonarInfo
from nav_bench.mapping import OccupancyGrid

DIFFBOT_ANGLES = np.radians([-90.0, -45.0, -15.0, 15.0, 45.0, 90.0])


def diffbot_sonar(max_range: float = 3.0) -> SonarInfo:
    """The default robot's ring: six 25 deg sonars on the body edge (0.18 m)."""
    offsets = 0.18 * np.stack([np.cos(DIFFBOT_ANGLES), np.sin(DIFFBOT_ANGLES)], 1)
    return SonarInfo(angles=DIFFBOT_ANGLES, offsets=offsets, cone=math.radians(25.0),
                     min_range=0.05, max_range=max_range)


def ray_box_distance(origin: np.ndarray, dirs: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """(R,) distance along each of (R, 2) unit ``dirs`` from ``origin`` (2,) to the nearest of
    (B, 4) boxes ``xmin, ymin, xmax, ymax`` (slab method); inf where a ray hits nothing."""
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / dirs[:, None, :]  # (R, 1, 2)
        t1 = (boxes[None, :, 0:2] - origin) * inv
        t2 = (boxes[None, :, 2:4] - origin) * inv
    near = np.nanmax(np.minimum(t1, t2), axis=2)
    far = np.nanmin(np.maximum(t1, t2), axis=2)
    hit = (far >= np.maximum(near, 0.0))
    return np.where(hit, np.maximum(near, 0.0), np.inf).min(axis=1)


def readings(pose: tuple[float, float, float], boxes: np.ndarray, sonar: SonarInfo,
             rays: int = 9) -> np.ndarray:
    """(K,) cone readings, m, of the sonars at robot ``pose`` (x, y, yaw) among ``boxes``."""
    x, y, yaw = pose
    out = np.empty(len(sonar.angles))
    spread = np.linspace(-sonar.cone / 2, sonar.cone / 2, rays)
    for k, (angle, (ox, oy)) in enumerate(zip(sonar.angles, sonar.offsets, strict=True)):
        origin = np.array([x + math.cos(yaw) * ox - math.sin(yaw) * oy,
                           y + math.sin(yaw) * ox + math.cos(yaw) * oy])
        a = yaw + angle + spread
        d = ray_box_distance(origin, np.stack([np.cos(a), np.sin(a)], 1), boxes).min()
        out[k] = min(max(d, sonar.min_range), sonar.max_range)
    return out


def brute_force(grid: OccupancyGrid, pose: np.ndarray, ranges: np.ndarray,
                sonar: SonarInfo) -> np.ndarray:
    """The grid's model ("elfes" or "band") cell by cell over the whole grid, one sonar after the
    other (reference for the vectorised update): the log-odds after fusing ``ranges``."""
    lo = grid.log_odds.copy()
    rows, cols = np.mgrid[0:grid.shape[0], 0:grid.shape[1]]
    centres = grid.cell_center(rows, cols)
    x, y, yaw = pose
    half_t, cell, half = grid.hit_thickness / 2, grid.cell, sonar.cone / 2
    for k, r in enumerate(ranges):
        ox, oy = sonar.offsets[k]
        sx = x + math.cos(yaw) * ox - math.sin(yaw) * oy
        sy = y + math.sin(yaw) * ox + math.cos(yaw) * oy
        a = yaw + sonar.angles[k]
        dx, dy = centres[..., 0] - sx, centres[..., 1] - sy
        along = dx * math.cos(a) + dy * math.sin(a)
        lateral = np.abs(dy * math.cos(a) - dx * math.sin(a))
        cone = (along > 0) & (lateral <= along * math.tan(half) + cell / 2)
        theta = np.arctan2(np.maximum(lateral - cell / 2, 0.0), along)
        w = np.clip(1 - (theta / half) ** 2, 0.0, 1.0)
        dist = np.hypot(dx, dy)
        echo = r < sonar.max_range
        free = cone & ((dist < r - half_t) if echo else (dist <= sonar.max_range))
        occ = cone & (np.abs(dist - r) <= half_t) & echo
        if grid.model == "band":
            delta = np.where(occ, grid.l_occ, np.where(free, grid.l_free, 0.0))
        else:
            blame = np.where(occ, w / (1 + np.exp(-lo)), 0.0)
            share = grid.echo_share * blame / blame.sum() if blame.sum() > 0 else blame
            delta = np.where(occ, grid.l_occ * np.minimum(1.0, share),
                             np.where(free, w * grid.l_free, 0.0))
        lo = np.clip(lo + delta, grid.l_min, grid.l_max)
    return lo
