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

MISS = 2.0  # the ray fraction a miss is given while cones are reduced (hits are in [0, 1])


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
    noise = rng.standard_normal(k)
    noise *= spec.noise_std
    lost = (rng.random(k) < spec.dropout).tolist()
    # six values: Python floats cost a fraction of NumPy's per-call overhead, with the same
    # IEEE operations (min/max of non-NaN floats as np.minimum/np.maximum)
    lo, hi = spec.min_range, spec.max_range
    return np.array([min(max(r + e, lo), hi) if h and not gone else hi
                     for r, e, h, gone in zip(ranges.tolist(), noise.tolist(), hit.tolist(), lost,
                                              strict=True)])


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
        self._max_range, self._min_range = float(spec.max_range), float(spec.min_range)
        self._direction = np.zeros((len(self._ray_yaw), 3))
        # the last cast's ray starts (N, 3), directions (N, 3) and fractions (N,), for drawing
        self._last: tuple[np.ndarray, np.ndarray, list[float]] | None = None

    def cast(self, position: tuple[float, float, float], rotation: np.ndarray
             ) -> tuple[np.ndarray, np.ndarray]:
        """True (noise-free) readings for a robot base frame at ``position`` / ``rotation``.

        Args:
            position: (3,) base frame origin in the world, m.
            rotation: (3, 3) base frame rotation matrix (columns: its axes in the world).
        Returns:
            ``(ranges (K,), hit (K,))``: clipped nearest hit per cone in m (max_range
            without echo) and whether the cone saw anything. :meth:`last_rays` draws them.
        """
        starts = self._ray_mount @ rotation.T
        starts += position
        heading = math.atan2(rotation[1, 0], rotation[0, 0])
        yaw = heading + self._ray_yaw  # horizontal rays even if the body pitches slightly
        direction = self._direction  # (N, 3), its z column stays 0
        np.cos(yaw, out=direction[:, 0])
        np.sin(yaw, out=direction[:, 1])
        ends = direction * self._max_range
        ends += starts
        results = self._cast(starts.tolist(), ends.tolist(), collisionFilterMask=RAY_MASK)
        # one pass over PyBullet's tuples; a miss (object id -1) gets MISS, above any hit's
        # fraction (at most 1), so a cone's minimum is its nearest hit if it has one
        fraction = [r[2] if r[0] >= 0 else MISS for r in results]
        n, lo, hi = self.rays, self._min_range, self._max_range
        nearest = [min(fraction[i:i + n]) for i in range(0, len(fraction), n)]
        hits = [f <= 1.0 for f in nearest]
        ranges = np.array([min(max(f * hi, lo), hi) if h else hi for f, h in zip(nearest, hits, strict=True)])
        cone_hit = np.array(hits)
        self._last = (starts, direction.copy(), fraction)
        return ranges, cone_hit

    def last_rays(self) -> RayBundle | None:
        """The rays of the last :meth:`cast`, for drawing (``None`` before the first)."""
        if self._last is None:
            return None
        starts, direction, fractions = self._last
        fraction = np.array(fractions)
        hit = fraction <= 1.0
        reach = np.where(hit, fraction, 1.0) * self._max_range
        return RayBundle(starts=starts, ends=starts + reach[:, None] * direction, hit=hit)
