"""Moving obstacles: where a mover is at time t (a pure function), and its PyBullet body.

A mover travels along its waypoints at constant speed. ``pingpong`` goes to the last
waypoint and back; ``loop`` returns from the last waypoint straight to the first. ``phase_s``
starts the motion that many seconds in. The position is a function of time only, so it is
the same in every run and can be computed by metrics and plots without a simulator.
"""

from __future__ import annotations

import bisect
import math

import numpy as np
import pybullet
from pybullet_utils.bullet_client import BulletClient

from nav_bench.specs import Mover

MOVER_RGBA = (0.85, 0.25, 0.20, 1.0)


class MoverPath:
    """A mover's route, precomputed for fast repeated queries.

    Attributes:
        points: (P, 2) route vertices, m (for ``loop`` the first point is repeated at the end).
        cumulative: (P,) distance along the route to each vertex, m.
        length: one-way route length, m (``pingpong`` has period 2 * length / speed).
    """

    def __init__(self, mover: Mover) -> None:
        pts = [tuple(map(float, p)) for p in mover.path]
        if mover.mode == "loop":
            pts.append(pts[0])
        self.points = np.asarray(pts, dtype=float)
        seg = np.hypot(*np.diff(self.points, axis=0).T)
        self.cumulative = np.concatenate([[0.0], np.cumsum(seg)])
        self.length = float(self.cumulative[-1])
        self.speed = float(mover.speed)
        self.phase_s = float(mover.phase_s)
        self.pingpong = mover.mode == "pingpong"
        self._pts = pts  # plain floats: faster than numpy for one query
        self._cum = self.cumulative.tolist()

    def at(self, t: float) -> tuple[float, float]:
        """Position (x, y) in m at time ``t`` s."""
        if self.length <= 0.0:
            return self._pts[0]
        s = self.speed * (t + self.phase_s)
        if self.pingpong:
            s = math.fmod(s, 2.0 * self.length)
            if s > self.length:
                s = 2.0 * self.length - s
        else:
            s = math.fmod(s, self.length)
        # Last vertex whose distance is <= s (zero-length segments are skipped).
        i = max(min(bisect.bisect_right(self._cum, s) - 1, len(self._pts) - 2), 0)
        span = self._cum[i + 1] - self._cum[i]
        f = (s - self._cum[i]) / span if span > 0.0 else 0.0
        (ax, ay), (bx, by) = self._pts[i], self._pts[i + 1]
        return (ax + f * (bx - ax), ay + f * (by - ay))


def mover_position(mover: Mover, t: float) -> tuple[float, float]:
    """Where ``mover`` is at time ``t`` (s since the episode start), in m."""
    return MoverPath(mover).at(t)


def mover_positions(movers: list[Mover], t: float) -> np.ndarray:
    """(M, 2) positions of all movers at time ``t``, m."""
    return np.asarray([mover_position(m, t) for m in movers], dtype=float).reshape(-1, 2)


class MoverBodies:
    """The movers of a world as kinematic PyBullet bodies.

    Each mover is a static (mass 0) body of height ``height`` placed at its path position
    before every physics step. Being static, it is never pushed; the robot it runs into is
    pushed out of it by the contact solver, and the contact is reported like any other.
    Box movers keep their orientation (axis-aligned) while they travel.
    """

    def __init__(self, client: BulletClient, movers: list[Mover], height: float,
                 gui: bool = False) -> None:
        self._client = client
        self.paths = [MoverPath(m) for m in movers]
        self.height = float(height)
        self._reset = client.resetBasePositionAndOrientation
        self.body_ids: tuple[int, ...] = tuple(
            self._create(m, gui) for m in movers)
        self.place(0.0)

    def _create(self, mover: Mover, gui: bool) -> int:
        c, h = self._client, self.height
        if mover.shape.cylinder is not None:
            r = float(mover.shape.cylinder.radius)
            kw = {"shapeType": pybullet.GEOM_CYLINDER, "radius": r}
            shape = c.createCollisionShape(height=h, **kw)
            visual = c.createVisualShape(length=h, rgbaColor=MOVER_RGBA, **kw) if gui else -1
        else:
            assert mover.shape.box is not None
            sx, sy = mover.shape.box.size
            kw = {"shapeType": pybullet.GEOM_BOX, "halfExtents": [sx / 2.0, sy / 2.0, h / 2.0]}
            shape = c.createCollisionShape(**kw)
            visual = c.createVisualShape(rgbaColor=MOVER_RGBA, **kw) if gui else -1
        # A multibody (not maximal coordinates): PyBullet refreshes its broadphase entry when
        # it is teleported, so rays and contacts see it at its new place.
        body = c.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=shape,
                                 baseVisualShapeIndex=visual)
        c.changeDynamics(body, -1, restitution=0.0)
        return body

    def place(self, t: float) -> None:
        """Move every body to its path position at time ``t`` s."""
        z = self.height / 2.0
        for body, path in zip(self.body_ids, self.paths, strict=True):
            x, y = path.at(t)
            self._reset(body, [x, y, z], [0.0, 0.0, 0.0, 1.0])

    def positions(self, t: float) -> np.ndarray:
        """(M, 2) positions at time ``t``, m."""
        return np.asarray([p.at(t) for p in self.paths], dtype=float).reshape(-1, 2)
