"""Static geometry of a world as a few compound PyBullet bodies.

One body per obstacle makes every physics step pay for every obstacle (PyBullet walks all
bodies each step). Instead, obstacles are grouped by place (recursive median splits, so a
group is a compact patch of the map) and each group becomes one static rigid body whose
collision shape is a compound of the group's boxes and cylinders. ``benchmarks/bench_sim.py``
measures it: with 1,000 boxes a physics step costs about 1.1x the empty world's, against
2x for one rigid body per box and 4-5x for one multibody per box.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pybullet
from pybullet_utils.bullet_client import BulletClient

from nav_bench.world.geometry import StaticGeometry

# PyBullet's createCollisionShapeArray keeps at most 16 child shapes and silently drops the
# rest (MAX_COMPOUND_COLLISION_SHAPES in its shared-memory protocol), so 16 is the ceiling.
MAX_SHAPES_PER_BODY = 16

WALL_RGBA = (0.55, 0.55, 0.58, 1.0)


@dataclass(frozen=True)
class SceneLayout:
    """How static obstacles become bodies (the defaults measure best; see bench_sim.py).

    Attributes:
        shapes_per_body: primitives per compound body, 1..16 (1: one body per obstacle).
        maximal_coordinates: static rigid bodies instead of static multibodies; PyBullet
            skips rigid ones in its per-step dynamics, but walks every multibody.
        group_by_place: group neighbours (:func:`spatial_chunks`); ``False`` groups in file
            order, so a body's bounding box spans the map and the robot overlaps many of them.
    """

    shapes_per_body: int = MAX_SHAPES_PER_BODY
    maximal_coordinates: bool = True
    group_by_place: bool = True


DEFAULT_LAYOUT = SceneLayout()


@dataclass(frozen=True)
class StaticScene:
    """The bodies holding a world's static obstacles.

    Attributes:
        body_ids: PyBullet ids of the compound bodies.
        shape_count: number of primitive shapes (boxes + cylinders) in them.
    """

    body_ids: tuple[int, ...]
    shape_count: int


def spatial_chunks(centers: np.ndarray, max_size: int) -> list[np.ndarray]:
    """Split points into groups of at most ``max_size`` that are compact in the plane.

    Recursive median bisection along the wider axis of each group; the split point is a
    multiple of ``max_size`` so nearly all groups are full (ceil(N / max_size) groups).

    Args:
        centers: (N, 2) points, m.
        max_size: largest group size (>= 1).
    Returns:
        Index arrays into ``centers``, deterministic for a given input.
    """
    if max_size < 1:
        raise ValueError(f"max_size must be >= 1, got {max_size}")
    pts = np.asarray(centers, dtype=float).reshape(-1, 2)
    out: list[np.ndarray] = []
    stack = [np.arange(len(pts))]
    while stack:
        idx = stack.pop()
        if len(idx) <= max_size:
            if len(idx):
                out.append(idx)
            continue
        sub = pts[idx]
        axis = 0 if np.ptp(sub[:, 0]) >= np.ptp(sub[:, 1]) else 1
        order = idx[np.argsort(sub[:, axis], kind="stable")]
        groups = math.ceil(len(idx) / max_size)
        cut = max_size * math.ceil(groups / 2)
        stack += [order[cut:], order[:cut]]  # popped left first: output runs left to right
    return out


def _yaw_quaternion(yaw: float) -> list[float]:
    return [0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)]


def build_static_scene(client: BulletClient, geometry: StaticGeometry, *, gui: bool = False,
                       layout: SceneLayout = DEFAULT_LAYOUT) -> StaticScene:
    """Add the world's static boxes and cylinders (height ``geometry.height``) as static bodies.

    Args:
        client: the session's client.
        geometry: from :func:`nav_bench.world.geometry.static_geometry`.
        gui: also create visual shapes (skipped headless: they cost memory and build time).
        layout: grouping of obstacles into bodies; the default is the fast one.
    """
    if not 1 <= layout.shapes_per_body <= MAX_SHAPES_PER_BODY:
        raise ValueError(f"shapes_per_body must be in 1..{MAX_SHAPES_PER_BODY}, "
                         f"got {layout.shapes_per_body}")
    h = float(geometry.height)
    boxes, cyls = geometry.boxes, geometry.cylinders
    centers = np.concatenate([boxes[:, :2], cyls[:, :2]]).reshape(-1, 2)
    n_boxes = len(boxes)
    body_ids = []
    n, k = len(centers), layout.shapes_per_body
    chunks = (spatial_chunks(centers, k) if layout.group_by_place
              else [np.arange(i, min(i + k, n)) for i in range(0, n, k)])
    for chunk in chunks:
        types, half_extents, radii, lengths, positions, orientations = [], [], [], [], [], []
        for i in chunk:
            if i < n_boxes:
                cx, cy, sx, sy, yaw = boxes[i]
                types.append(pybullet.GEOM_BOX)
                half_extents.append([sx / 2.0, sy / 2.0, h / 2.0])
                radii.append(0.0)
                orientations.append(_yaw_quaternion(yaw))
            else:
                cx, cy, r = cyls[i - n_boxes]
                types.append(pybullet.GEOM_CYLINDER)
                half_extents.append([0.0, 0.0, 0.0])
                radii.append(float(r))
                orientations.append([0.0, 0.0, 0.0, 1.0])
            lengths.append(h)
            positions.append([float(cx), float(cy), h / 2.0])
        body = _static_body(client, types, radii, half_extents, lengths, positions,
                            orientations, gui, layout.maximal_coordinates)
        client.changeDynamics(body, -1, restitution=0.0)
        body_ids.append(body)
    return StaticScene(body_ids=tuple(body_ids), shape_count=len(centers))


def _static_body(client: BulletClient, types: list[int], radii: list[float],
                 half_extents: list[list[float]], lengths: list[float],
                 positions: list[list[float]], orientations: list[list[float]], gui: bool,
                 maximal_coordinates: bool) -> int:
    """One static body holding the given primitives (world-frame poses)."""
    if len(types) == 1:  # a plain shape placed by the body pose: the one-body-per-box layout
        shape = client.createCollisionShape(types[0], radius=radii[0],
                                            halfExtents=half_extents[0], height=lengths[0])
        visual = client.createVisualShape(types[0], radius=radii[0], halfExtents=half_extents[0],
                                          length=lengths[0], rgbaColor=WALL_RGBA) if gui else -1
        pose = {"basePosition": positions[0], "baseOrientation": orientations[0]}
    else:
        shape = client.createCollisionShapeArray(
            shapeTypes=types, radii=radii, halfExtents=half_extents, lengths=lengths,
            collisionFramePositions=positions, collisionFrameOrientations=orientations)
        visual = client.createVisualShapeArray(
            shapeTypes=types, radii=radii, halfExtents=half_extents, lengths=lengths,
            rgbaColors=[WALL_RGBA] * len(types), visualFramePositions=positions,
            visualFrameOrientations=orientations) if gui else -1
        pose = {}
    return client.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=shape,
                                  baseVisualShapeIndex=visual,
                                  useMaximalCoordinates=maximal_coordinates, **pose)
