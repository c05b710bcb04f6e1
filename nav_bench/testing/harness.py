"""A tiny kinematic harness to drive planners in tests, without PyBullet.

* World: axis-aligned boxes ``(xmin, ymin, xmax, ymax)`` in metres, built directly, from a
  room outline (:meth:`BoxWorld.room`) or from a boolean occupancy grid
  (:meth:`BoxWorld.from_grid`, row 0 at the bottom).
* Robot: a disc of radius ``robot.radius`` moving as a unicycle. Each control period
  ``dt`` (0.1 s = 10 Hz) the command is clipped to the robot's limits and integrated exactly
  (circular arcs) in ``substeps`` sub-steps; a sub-step that would bring the disc into a box
  is not taken (the robot stops against it) and the contact is counted once per touch.
* Sonars: the default ring (-90, -45, -15, 15, 45, 90 deg, mounted on the body edge),
  each a 25 deg cone of ``rays`` rays; the reading is the shortest ray hit, clipped to
  ``[min_range, max_range]`` (0.05..3 m); ``max_range`` means no echo. Optional Gaussian
  noise from the seeded generator.
* Odometry is perfect: the planner's pose is the true pose.

:func:`run` returns the trajectory, the commands and whether the goal was reached.
One episode of 60 s simulated time takes ~0.1 s plus the planner's own time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from nav_bench.interface import Command, Observation, RobotInfo, SonarInfo
from nav_bench.planners.base import Planner

SONAR_ANGLES_DEG = (-90.0, -45.0, -15.0, 15.0, 45.0, 90.0)


def default_robot(radius: float = 0.2, v_max: float = 0.5, omega_max: float = 2.0,
                  wheel_base: float = 0.3, max_range: float = 3.0) -> RobotInfo:
    """The test robot: a 0.2 m disc, 0.5 m/s, 2 rad/s, six sonars on its edge."""
    ang = np.radians(SONAR_ANGLES_DEG)
    sonar = SonarInfo(angles=ang, offsets=radius * np.stack([np.cos(ang), np.sin(ang)], axis=1),
                      cone=math.radians(25.0), min_range=0.05, max_range=max_range)
    return RobotInfo(radius=radius, wheel_base=wheel_base, v_max=v_max, omega_max=omega_max,
                     sonar=sonar)


@dataclass(frozen=True)
class BoxWorld:
    """Axis-aligned boxes (N, 4) ``xmin, ymin, xmax, ymax`` and the area ``bounds`` (m)."""

    boxes: np.ndarray
    bounds: tuple[float, float, float, float]

    @classmethod
    def room(cls, size: tuple[float, float], boxes: list[tuple[float, float, float, float]] = (),
             wall: float = 0.1) -> BoxWorld:
        """A ``size`` (sx, sy) room with walls just outside ``[0, sx] x [0, sy]`` plus ``boxes``."""
        sx, sy = size
        outline = [(-wall, -wall, sx + wall, 0.0), (-wall, sy, sx + wall, sy + wall),
                   (-wall, 0.0, 0.0, sy), (sx, 0.0, sx + wall, sy)]
        return cls(np.array(outline + list(boxes), dtype=float).reshape(-1, 4), (0.0, 0.0, sx, sy))

    @classmethod
    def from_grid(cls, occupied: np.ndarray, cell: float,
                  origin: tuple[float, float] = (0.0, 0.0)) -> BoxWorld:
        """Boxes from a boolean grid (row 0 at y = origin y); each row's runs become one box."""
        occ = np.asarray(occupied, dtype=bool)
        x0, y0 = origin
        boxes = []
        for r in range(occ.shape[0]):
            padded = np.concatenate([[False], occ[r], [False]])
            edges = np.flatnonzero(padded[1:] != padded[:-1])
            for c0, c1 in zip(edges[0::2], edges[1::2], strict=True):
                boxes.append((x0 + c0 * cell, y0 + r * cell, x0 + c1 * cell, y0 + (r + 1) * cell))
        h, w = occ.shape
        return cls(np.array(boxes, dtype=float).reshape(-1, 4), (x0, y0, x0 + w * cell, y0 + h * cell))

    def cast(self, origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
        """(R,) distance along each unit ray to the first box (0 if it starts inside, inf if none)."""
        if len(self.boxes) == 0:
            return np.full(len(origins), np.inf)
        d = np.where(np.abs(directions) < 1e-12, 1e-12, directions)
        lo = (self.boxes[None, :, :2] - origins[:, None, :]) / d[:, None, :]  # (R, N, 2)
        hi = (self.boxes[None, :, 2:] - origins[:, None, :]) / d[:, None, :]
        t_near = np.minimum(lo, hi).max(axis=2)
        t_far = np.maximum(lo, hi).min(axis=2)
        hit = t_far >= np.maximum(t_near, 0.0)
        t = np.where(hit, np.maximum(t_near, 0.0), np.inf)
        return t.min(axis=1)

    def clearance(self, xy: np.ndarray) -> float:
        """Distance (m) from a point to the nearest box (0 inside one)."""
        if len(self.boxes) == 0:
            return math.inf
        dx = np.maximum.reduce([self.boxes[:, 0] - xy[0], np.zeros(len(self.boxes)), xy[0] - self.boxes[:, 2]])
        dy = np.maximum.reduce([self.boxes[:, 1] - xy[1], np.zeros(len(self.boxes)), xy[1] - self.boxes[:, 3]])
        return float(np.hypot(dx, dy).min())


def sense(world: BoxWorld, pose: np.ndarray, robot: RobotInfo, rays: int = 5,
          noise_std: float = 0.0, rng: np.random.Generator | None = None) -> np.ndarray:
    """(K,) sonar readings at ``pose``, m (see the module docstring)."""
    s = robot.sonar
    x, y, yaw = pose
    c, si = math.cos(yaw), math.sin(yaw)
    ox, oy = s.mounts(x, y, c, si)
    spread = np.linspace(-s.cone / 2, s.cone / 2, rays)
    ang = (yaw + s.angles)[:, None] + spread[None, :]  # (K, rays)
    origins = np.repeat(np.stack([ox, oy], axis=1), rays, axis=0)
    dirs = np.stack([np.cos(ang).ravel(), np.sin(ang).ravel()], axis=1)
    r = world.cast(origins, dirs).reshape(len(s.angles), rays).min(axis=1)
    if noise_std > 0 and rng is not None:
        r = np.where(np.isfinite(r), r + rng.normal(0.0, noise_std, len(r)), r)
    return np.clip(np.where(np.isfinite(r), r, s.max_range), s.min_range, s.max_range)


@dataclass
class Run:
    """The outcome of :func:`run`.

    Attributes:
        poses: (T+1, 3) poses x, y, yaw from the start. commands: (T, 2) v, omega as returned.
        reached: goal within tolerance. time: simulated s. collisions: distinct touches.
        events: planner events as (kind, t, data). planner: the planner after the run.
    """

    poses: np.ndarray
    commands: np.ndarray
    reached: bool
    time: float
    collisions: int
    events: list[tuple[str, float, dict[str, Any]]] = field(default_factory=list)
    planner: Planner | None = None

    @property
    def path_length(self) -> float:
        return float(np.hypot(*np.diff(self.poses[:, :2], axis=0).T).sum())

    def kinds(self, kind: str) -> int:
        return sum(1 for k, _, _ in self.events if k == kind)


def observe(world: BoxWorld, pose: np.ndarray, goal: np.ndarray, robot: RobotInfo, t: float,
            dt: float, rays: int = 5, noise_std: float = 0.0,
            rng: np.random.Generator | None = None) -> Observation:
    """The observation a planner gets at ``pose`` (perfect odometry)."""
    return Observation(t=t, pose=pose.copy(), goal=np.asarray(goal, dtype=float), robot=robot,
                       ranges=sense(world, pose, robot, rays, noise_std, rng),
                       bounds=world.bounds, dt=dt)


def run(planner: Planner, world: BoxWorld, start: tuple[float, float, float],
        goal: tuple[float, float], *, time_s: float = 60.0, seed: int = 0, dt: float = 0.1,
        goal_tolerance: float = 0.2, robot: RobotInfo | None = None, noise_std: float = 0.0,
        rays: int = 5, substeps: int = 5, reset: bool = True) -> Run:
    """Drive ``planner`` from ``start`` (x, y, yaw rad) toward ``goal`` for up to ``time_s`` s.

    The planner is reset with ``np.random.default_rng(seed)`` (the same generator drives the
    sonar noise). Ends when the goal is within ``goal_tolerance`` m of the robot centre.
    """
    robot = robot or default_robot()
    rng = np.random.default_rng(seed)
    goal_xy = np.asarray(goal, dtype=float)
    pose = np.asarray(start, dtype=float)
    poses, commands, events = [pose.copy()], [], []
    collisions, touching, t = 0, False, 0.0
    obs = observe(world, pose, goal_xy, robot, t, dt, rays, noise_std, rng)
    if reset:
        planner.reset(obs, rng)
    reached = False
    for _ in range(round(time_s / dt)):
        if np.hypot(*(pose[:2] - goal_xy)) < goal_tolerance:
            reached = True
            break
        cmd: Command = planner.act(obs)
        events += [(e.kind, e.t, dict(e.data)) for e in planner.pop_events()]
        commands.append((cmd.v, cmd.omega))
        v = max(-robot.v_max, min(robot.v_max, cmd.v))
        w = max(-robot.omega_max, min(robot.omega_max, cmd.omega))
        h = dt / substeps
        for _ in range(substeps):
            x, y, yaw = pose
            if abs(w) > 1e-9:
                nx = x + v / w * (math.sin(yaw + w * h) - math.sin(yaw))
                ny = y - v / w * (math.cos(yaw + w * h) - math.cos(yaw))
            else:
                nx, ny = x + v * h * math.cos(yaw), y + v * h * math.sin(yaw)
            nyaw = math.remainder(yaw + w * h, 2 * math.pi)
            if world.clearance(np.array([nx, ny])) < robot.radius:
                collisions += 0 if touching else 1
                touching = True
                pose = np.array([x, y, nyaw])  # blocked: turn only
            else:
                touching = False
                pose = np.array([nx, ny, nyaw])
        t += dt
        poses.append(pose.copy())
        obs = observe(world, pose, goal_xy, robot, t, dt, rays, noise_std, rng)
    else:
        reached = bool(np.hypot(*(pose[:2] - goal_xy)) < goal_tolerance)
    return Run(poses=np.array(poses), commands=np.array(commands, dtype=float).reshape(-1, 2),
               reached=reached, time=t, collisions=collisions, events=events, planner=planner)


# ----------------------------------------------------------------------------- test worlds
def wall_world() -> tuple[BoxWorld, tuple[float, float, float], tuple[float, float]]:
    """8 x 6 m room, a 3 m wall across the straight line at x = 4 (start left, goal right)."""
    world = BoxWorld.room((8.0, 6.0), [(3.9, 1.5, 4.1, 4.5)])
    return world, (1.0, 3.0, 0.0), (7.0, 3.0)


def u_world() -> tuple[BoxWorld, tuple[float, float, float], tuple[float, float]]:
    """10 x 8 m room, a U open toward the start (arms 2 m, 2.4 m wide); the goal is behind its
    bottom, so the straight line leads into the U."""
    boxes = [(5.0, 2.6, 5.15, 5.4),   # bottom of the U, facing the start
             (3.0, 2.6, 5.15, 2.75),  # lower arm
             (3.0, 5.25, 5.15, 5.4)]  # upper arm
    return BoxWorld.room((10.0, 8.0), boxes), (1.0, 4.0, 0.0), (8.0, 4.0)


def open_room() -> tuple[BoxWorld, tuple[float, float, float], tuple[float, float]]:
    """An empty 6 x 5 m room; start lower left facing away from the goal, goal upper right."""
    return BoxWorld.room((6.0, 5.0)), (1.0, 1.0, math.pi / 2 + 0.3), (5.0, 4.0)
