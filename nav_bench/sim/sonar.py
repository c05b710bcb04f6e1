"""Ray-cast sonars: each sonar is a cone of rays; all cones are cast in one ``rayTestBatch``.

A reading is the nearest hit over the cone's rays, clipped to [min_range, max_range]; a cone
that hits nothing reads ``max_range`` ("no echo"). Noise and dropout come from the episode's
generator (:func:`noisy_readings`). Rays start at the sonar frame and run horizontally at its
height; the robot is excluded by collision-filter mask, so only walls and movers echo (the
rays run above the floor and never reach it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from pybullet_utils.bullet_client import BulletClient

from nav_bench.sim.session import RAY_MASK
from nav_bench.specs import SonarSpec


@dataclass(frozen=True)
class RayBundle:
    """The rays of one sensing call, for drawing.

    Attributes:
        starts: (N, 3) ray origins, m (N = sonars x rays per cone, sonar-major order).
        ends: (N, 3) hit points, or the ray end at max range when nothing was hit, m.
        hit: (N,) whether each ray hit something.
    """

    starts: np.ndarray
    ends: np.ndarray
    hit: np.ndarray


def cone_offsets(cone: float, rays: int) -> np.ndarray:
    """(rays,) ray directions relative to the sonar axis, rad, evenly spread over ``cone``.

    The outermost rays lie on the cone's edges; a single ray lies on the axis.
    """
    if rays == 1:
        return np.zeros(1)
    return np.linspace(-cone / 2.0, cone / 2.0, rays)


def noisy_readings(ranges: np.ndarray, hit: np.ndarray, spec: SonarSpec,
                   rng: np.random.Generator) -> np.ndarray:
    """Sensor noise on true readings.

    Echoes get Gaussian noise (std ``noise_std``) and are clipped to [min_range, max_range];
    then each reading is lost with probability ``dropout`` and reads ``max_range``. A cone
    without echo keeps reading exactly ``max_range``. The generator is advanced by the same
    amount (K normals, then K uniforms) whatever the readings and settings, so the random
    stream of an episode does not depend on what the robot happened to see.

    Args:
        ranges: (K,) true readings, m. hit: (K,) bool, the cone saw something.
    Returns:
        (K,) readings, m.
    """
    k = len(ranges)
    noise = rng.standard_normal(k) * spec.noise_std
    lost = rng.random(k) < spec.dropout
    out = np.where(hit, np.clip(ranges + noise, spec.min_range, spec.max_range), spec.max_range)
    return np.where(lost, spec.max_range, out)


class SonarArray:
    """The robot's sonars, cast together.

    Args:
        client: the session's client.
        mounts: (K, 3) sonar origins in the robot base frame, m.
        yaws: (K,) sonar axis yaws relative to the heading, rad.
        spec: cone, rays, range and noise settings.
    """

    def __init__(self, client: BulletClient, mounts: np.ndarray, yaws: np.ndarray,
                 spec: SonarSpec) -> None:
        self.spec = spec
        self.mounts = np.asarray(mounts, dtype=float).reshape(-1, 3)
        self.yaws = np.asarray(yaws, dtype=float).reshape(-1)
        self.count = len(self.yaws)
        self.rays = int(spec.rays)
        spread = cone_offsets(math.radians(spec.cone_deg), self.rays)
        # (K * R,) ray yaw in the base frame and the sonar each ray belongs to, sonar-major.
        self._ray_yaw = (self.yaws[:, None] + spread[None, :]).reshape(-1)
        self._ray_mount = np.repeat(self.mounts, self.rays, axis=0)
        self._cast = client.rayTestBatch

    def cast(self, position: tuple[float, float, float], rotation: np.ndarray
             ) -> tuple[np.ndarray, np.ndarray, RayBundle]:
        """True (noise-free) readings for a robot base frame at ``position`` / ``rotation``.

        Args:
            position: (3,) base frame origin in the world, m.
            rotation: (3, 3) base frame rotation matrix (columns: its axes in the world).
        Returns:
            ``(ranges (K,), hit (K,), rays)``: clipped nearest hit per cone in m (max_range
            without echo), whether the cone saw anything, and the rays for drawing.
        """
        spec = self.spec
        starts = self._ray_mount @ rotation.T + np.asarray(position)
        heading = math.atan2(rotation[1, 0], rotation[0, 0])
        yaw = heading + self._ray_yaw  # horizontal rays even if the body pitches slightly
        direction = np.stack([np.cos(yaw), np.sin(yaw), np.zeros_like(yaw)], axis=1)
        ends = starts + spec.max_range * direction
        results = self._cast(starts.tolist(), ends.tolist(), collisionFilterMask=RAY_MASK)
        hit = np.fromiter((r[0] >= 0 for r in results), dtype=bool, count=len(results))
        fraction = np.fromiter((r[2] for r in results), dtype=float, count=len(results))
        fraction = np.where(hit, fraction, 1.0)
        distance = (fraction * spec.max_range).reshape(self.count, self.rays)
        cone_hit = hit.reshape(self.count, self.rays).any(axis=1)
        ranges = np.where(cone_hit, np.clip(distance.min(axis=1), spec.min_range, spec.max_range),
                          spec.max_range)
        bundle = RayBundle(starts=starts, ends=starts + (fraction * spec.max_range)[:, None]
                           * direction, hit=hit)
        return ranges, cone_hit, bundle
