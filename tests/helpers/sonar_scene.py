"""A tiny ray-cast sonar over axis-aligned boxes, for testing the sensor model without PyBullet.

Same reading rule as ``nav_bench.sim.sonar``: the nearest hit over rays evenly spread across
the cone (edges included), ``max_range`` when no ray hits.
"""

from __future__ import annotations

import math

import numpy as np

from nav_bench.interface import SonarInfo

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
