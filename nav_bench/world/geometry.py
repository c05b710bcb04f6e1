"""A world spec as flat arrays of primitives (oriented boxes and cylinders).

Everything that needs the true geometry (scene building, rasterising, clearance,
plots) starts from :func:`static_geometry`, so walls and polylines are turned into
boxes in exactly one place.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from nav_bench.errors import SpecError, format_key_path
from nav_bench.specs import GOAL_TOLERANCE_M, Mover, WorldSpec
from nav_bench.yamlio import LineIndex

BOUNDARY_THICKNESS = 0.15  # m, boundary walls lie just outside [0, sx] x [0, sy]


@dataclass(frozen=True)
class StaticGeometry:
    """Static obstacles of a world.

    Attributes:
        boxes: (N, 5) float array of ``cx, cy, sx, sy, yaw`` (m, m, m, m, rad); sx, sy full sizes.
        cylinders: (M, 3) float array of ``cx, cy, radius`` (m).
        box_source: N indices into ``world.obstacles`` (-1 for boundary walls).
        cylinder_source: M indices into ``world.obstacles``.
        height: wall height (m).
        size: world size (sx, sy) in m.
    """

    boxes: np.ndarray
    cylinders: np.ndarray
    box_source: np.ndarray
    cylinder_source: np.ndarray
    height: float
    size: tuple[float, float]

    @property
    def count(self) -> int:
        return len(self.boxes) + len(self.cylinders)


def segment_box(a: tuple[float, float], b: tuple[float, float], thickness: float) -> list[float]:
    """The box (cx, cy, length, thickness, yaw) of a wall from ``a`` to ``b``.

    The wall is extended by half its thickness at both ends so chained walls close their corners.
    """
    (ax, ay), (bx, by) = a, b
    length = math.hypot(bx - ax, by - ay)
    return [(ax + bx) / 2, (ay + by) / 2, length + thickness, thickness, math.atan2(by - ay, bx - ax)]


def static_geometry(world: WorldSpec) -> StaticGeometry:
    """Flatten the world's static obstacles (and boundary walls) into primitive arrays."""
    boxes: list[list[float]] = []
    box_src: list[int] = []
    cyls: list[list[float]] = []
    cyl_src: list[int] = []
    for i, obstacle in enumerate(world.obstacles):
        kind, shape = obstacle.kind, obstacle.shape
        if kind == "wall":
            boxes.append(segment_box(shape.from_, shape.to, shape.thickness))
            box_src.append(i)
        elif kind == "box":
            boxes.append([*shape.center, *shape.size, math.radians(shape.yaw_deg)])
            box_src.append(i)
        elif kind == "cylinder":
            cyls.append([*shape.center, shape.radius])
            cyl_src.append(i)
        elif kind == "polyline":
            pts = list(shape.points) + ([shape.points[0]] if shape.closed else [])
            for a, b in itertools.pairwise(pts):
                if a != b:
                    boxes.append(segment_box(a, b, shape.thickness))
                    box_src.append(i)
    if world.boundary:
        sx, sy = world.size
        t = BOUNDARY_THICKNESS
        boxes += [
            [sx / 2, -t / 2, sx + 2 * t, t, 0.0],
            [sx / 2, sy + t / 2, sx + 2 * t, t, 0.0],
            [-t / 2, sy / 2, t, sy, 0.0],
            [sx + t / 2, sy / 2, t, sy, 0.0],
        ]
        box_src += [-1] * 4
    return StaticGeometry(
        boxes=np.asarray(boxes, dtype=float).reshape(-1, 5),
        cylinders=np.asarray(cyls, dtype=float).reshape(-1, 3),
        box_source=np.asarray(box_src, dtype=int),
        cylinder_source=np.asarray(cyl_src, dtype=int),
        height=world.wall_height,
        size=(float(world.size[0]), float(world.size[1])),
    )


def box_corners(boxes: np.ndarray) -> np.ndarray:
    """(N, 4, 2) corners, counter-clockwise, of (N, 5) boxes ``cx, cy, sx, sy, yaw`` (m, rad)."""
    b = np.asarray(boxes, dtype=float).reshape(-1, 5)
    c, s = np.cos(b[:, 4])[:, None], np.sin(b[:, 4])[:, None]
    signs = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
    lx = signs[None, :, 0] * (b[:, 2] / 2)[:, None]
    ly = signs[None, :, 1] * (b[:, 3] / 2)[:, None]
    return np.stack([b[:, None, 0] + c * lx - s * ly, b[:, None, 1] + s * lx + c * ly], axis=-1)


def box_signed_distance(points: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """(K, N) signed distance (m) from (K, 2) points to (N, 5) boxes; negative inside."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    b = np.asarray(boxes, dtype=float).reshape(-1, 5)
    c, s = np.cos(b[:, 4]), np.sin(b[:, 4])
    return _box_distance(p[:, None, 0] - b[None, :, 0], p[:, None, 1] - b[None, :, 1],
                         c, s, -s, b[:, 2] / 2, b[:, 3] / 2)


def _box_distance(dx: np.ndarray, dy: np.ndarray, cos: np.ndarray, sin: np.ndarray,
                  neg_sin: np.ndarray, half_x: np.ndarray, half_y: np.ndarray) -> np.ndarray:
    """Signed distance (m) from offsets ``dx``, ``dy`` (point minus box centre, (..., N)) to
    boxes of yaw cosine ``cos``, sine ``sin`` (and ``-sin``) and half sizes ``half_x``,
    ``half_y`` (N,); negative inside."""
    lx = np.abs(cos * dx + sin * dy) - half_x  # box frame, minus half extents
    ly = np.abs(neg_sin * dx + cos * dy) - half_y
    return np.hypot(np.maximum(lx, 0), np.maximum(ly, 0)) + np.minimum(np.maximum(lx, ly), 0)


def polyline_length(points: np.ndarray) -> float:
    """Length (m) of the polyline through (N, 2) points (0 for fewer than two)."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    return float(np.hypot(*np.diff(p, axis=0).T).sum()) if len(p) > 1 else 0.0


def signed_distances(geometry: StaticGeometry, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Signed distance from each point to every primitive (negative inside).

    Args:
        points: (K, 2) array of x, y in m.
    Returns:
        ``(d_boxes, d_cylinders)`` of shapes (K, N) and (K, M), in m.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    d_boxes = box_signed_distance(pts, geometry.boxes)
    cy = geometry.cylinders
    if len(cy):
        d_cyl = np.hypot(pts[:, None, 0] - cy[None, :, 0], pts[:, None, 1] - cy[None, :, 1]) - cy[:, 2]
    else:
        d_cyl = np.zeros((len(pts), 0))
    return d_boxes, d_cyl


def clearance(geometry: StaticGeometry, points: np.ndarray, chunk: int = 2048) -> np.ndarray:
    """Distance (m) from each of (K, 2) points to the nearest static obstacle; negative inside."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    out = np.full(len(pts), np.inf)
    for start in range(0, len(pts), chunk):  # bounded memory for long traces x many obstacles
        db, dc = signed_distances(geometry, pts[start:start + chunk])
        both = np.concatenate([db, dc], axis=1)
        if both.shape[1]:
            out[start:start + chunk] = both.min(axis=1)
    return out


class PointClearance:
    """Distance (m) from one point to the nearest static obstacle, for queries in a loop.

    The arithmetic of :func:`clearance` on a single point (the same :func:`_box_distance`
    formula), bit for bit, at a fraction of its cost; the simulation asks it up to once per
    control cycle (:class:`~nav_bench.sim.contacts.ContactWindow`), mostly near walls.

    Near obstacles a query reads only the few primitives that can be the nearest: the world is
    cut into ``bucket`` m squares, and each square lists, when first queried, the primitives
    within ``reach`` m of any of its points. A point whose nearest listed primitive lies within
    ``reach`` has its answer there, in plain floats (a paper world's 4-25 primitives cost a
    dozen NumPy calls, 15-30 us; a square's list, a few us). Elsewhere (open space, outside the
    world) every primitive is measured with NumPy, each box's sine, cosine and half sizes
    computed once.

    Args:
        geometry: the world's static obstacles.
        bucket: side of the squares, m.
        reach: distance within which a square's list holds every primitive, m.
    """

    def __init__(self, geometry: StaticGeometry, bucket: float = 0.5, reach: float = 1.0) -> None:
        b = np.asarray(geometry.boxes, dtype=float).reshape(-1, 5)
        self._box_x, self._box_y = b[:, 0].copy(), b[:, 1].copy()
        self._cos, self._sin = np.cos(b[:, 4]), np.sin(b[:, 4])
        self._neg_sin = -self._sin
        self._half_x, self._half_y = b[:, 2] / 2, b[:, 3] / 2
        cy = np.asarray(geometry.cylinders, dtype=float).reshape(-1, 3)
        self._cyl_x, self._cyl_y, self._cyl_r = cy[:, 0].copy(), cy[:, 1].copy(), cy[:, 2].copy()
        # the same numbers as Python floats, one tuple per primitive, for the squares' lists
        self._box_rows = list(zip(*(a.tolist() for a in (
            self._box_x, self._box_y, self._cos, self._sin, self._neg_sin, self._half_x,
            self._half_y)), strict=True))
        self._cyl_rows = list(zip(*(a.tolist() for a in (self._cyl_x, self._cyl_y, self._cyl_r)),
                                  strict=True))
        self.bucket, self.reach = float(bucket), float(reach)
        self._cols = max(1, math.ceil(geometry.size[0] / self.bucket))
        self._rows = max(1, math.ceil(geometry.size[1] / self.bucket))
        self._near: dict[int, tuple[list[tuple[float, ...]], list[tuple[float, ...]]]] = {}
        self._row_near: dict[int, tuple[tuple[np.ndarray, np.ndarray], ...]] = {}  # a row at a time
        # half the height of each box's bounding box (its reach along y from its centre), m
        self._box_extent_y = np.abs(self._sin) * self._half_x + np.abs(self._cos) * self._half_y

    def __call__(self, x: float, y: float) -> float:
        """Signed distance (m) from (x, y) to the nearest obstacle (negative inside; inf if none)."""
        col, row = math.floor(x / self.bucket), math.floor(y / self.bucket)
        if 0 <= col < self._cols and 0 <= row < self._rows:
            key = row * self._cols + col
            near = self._near.get(key)
            if near is None:
                near = self._near[key] = self._primitives_near(col, row)
            best = _nearest_listed(x, y, *near)
            if best <= self.reach:  # every primitive not listed is farther than reach
                return best
        return self._nearest_of_all(x, y)

    def _nearest_of_all(self, x: float, y: float) -> float:
        best = math.inf
        if len(self._box_x):
            best = float(_box_distance(x - self._box_x, y - self._box_y, self._cos, self._sin,
                                       self._neg_sin, self._half_x, self._half_y).min())
        if len(self._cyl_x):
            d = np.hypot(x - self._cyl_x, y - self._cyl_y) - self._cyl_r
            best = min(best, float(d.min()))
        return best

    def _primitives_near(self, col: int, row: int
                         ) -> tuple[list[tuple[float, ...]], list[tuple[float, ...]]]:
        """The boxes and cylinders within ``reach`` of some point of square (col, row)."""
        near = self._row_near.get(row)
        if near is None:
            near = self._row_near[row] = self._near_in_row(row)
        (box_ids, boxes), (cyl_ids, cylinders) = near
        return ([self._box_rows[i] for i in box_ids[boxes[col]].tolist()],
                [self._cyl_rows[i] for i in cyl_ids[cylinders[col]].tolist()])

    def _near_in_row(self, row: int) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
        """Which primitives are near each square of a row of squares, for boxes and for
        cylinders: ``(ids, near)``, the primitives whose bounding box reaches the row's band
        ((K,) indices) and, (cols, K), which of those are near each square. Near: within
        reach + half a square's diagonal of its centre (distances are 1-Lipschitz), with a
        micrometre to spare for rounding; a primitive that near a centre has its bounding box
        within that distance of the centre's row, so the band loses none."""
        cx = ((np.arange(self._cols) + 0.5) * self.bucket)[:, None]
        cy = (row + 0.5) * self.bucket
        radius = self.reach + self.bucket * math.sqrt(0.5) + 1e-6
        b = np.flatnonzero(np.abs(self._box_y - cy) <= radius + self._box_extent_y)
        boxes = _box_distance(cx - self._box_x[b], cy - self._box_y[b], self._cos[b],
                              self._sin[b], self._neg_sin[b], self._half_x[b],
                              self._half_y[b]) <= radius
        c = np.flatnonzero(np.abs(self._cyl_y - cy) <= radius + self._cyl_r)
        cylinders = np.hypot(cx - self._cyl_x[c], cy - self._cyl_y[c]) - self._cyl_r[c] <= radius
        return (b, boxes), (c, cylinders)


def _nearest_listed(x: float, y: float, boxes: list[tuple[float, ...]],
                    cylinders: list[tuple[float, ...]]) -> float:
    """:func:`_box_distance` and the cylinders' distance, one primitive at a time in Python
    floats, minimum over the given primitives (inf if none). The same IEEE operations as the
    NumPy formula: ``np.hypot`` (``math.hypot`` may differ in the last bit), and only off a
    corner, as ``hypot(l, 0) = |l|`` exactly (C99 F.10.4.3) and a box is never nearer than
    ``max(lx, ly)``."""
    best = math.inf
    for bx, by, cos, sin, neg_sin, half_x, half_y in boxes:
        dx, dy = x - bx, y - by
        lx = abs(cos * dx + sin * dy) - half_x  # box frame, minus half extents
        ly = abs(neg_sin * dx + cos * dy) - half_y
        if lx > 0.0 and ly > 0.0:  # off a corner
            if max(lx, ly) < best:
                best = min(best, float(np.hypot(lx, ly)))
        elif lx > 0.0 or ly > 0.0:  # off a side: hypot(l, 0) + 0
            best = min(best, max(lx, ly) + 0.0)
        else:  # inside: hypot(0, 0) + max(lx, ly)
            best = min(best, 0.0 + max(lx, ly))
    for px, py, radius in cylinders:
        best = min(best, float(np.hypot(x - px, y - py)) - radius)
    return best


def obstacle_containing(geometry: StaticGeometry, xy: tuple[float, float], margin: float = 0.0) -> int | None:
    """Index into ``world.obstacles`` of an obstacle within ``margin`` of ``xy`` (-1: boundary)."""
    db, dc = signed_distances(geometry, np.asarray([xy]))
    if db.size and db.min() < margin:
        return int(geometry.box_source[int(np.argmin(db[0]))])
    if dc.size and dc.min() < margin:
        return int(geometry.cylinder_source[int(np.argmin(dc[0]))])
    return None


def check_goal_distance(world: WorldSpec, goal_tolerance: float, *,
                        file: str | Path | None = None, index: LineIndex | None = None) -> None:
    """Refuse a world whose goal lies within ``goal_tolerance`` (the success radius) of its
    start: the episode would "succeed" at once."""
    gap = math.dist(world.start[:2], world.goal)
    if gap <= goal_tolerance:
        raise SpecError(f"({world.goal[0]:g}, {world.goal[1]:g}) lies {gap:.3g} m from the start, "
                        f"within the success radius of {goal_tolerance:g} m; expected a goal "
                        f"farther away", file=file, key_path="goal",
                        line=index.line_of(("goal",)) if index else None)


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


def check_world_geometry(world: WorldSpec, *, file: str | Path | None = None,
                         index: LineIndex | None = None) -> None:
    """Refuse a world whose start or goal lies outside it or inside an obstacle, or whose goal
    lies within the default success radius of its start."""
    from nav_bench.world.raster import RASTER_CELL_M, grid_shape, raster_budget_problem

    sx, sy = world.size
    problem = raster_budget_problem(grid_shape((0.0, 0.0, sx, sy), RASTER_CELL_M), RASTER_CELL_M)
    if problem is not None:
        raise SpecError(f"a {sx:g} m x {sy:g} m world {problem}", file=file, key_path="size",
                        line=index.line_of(("size",)) if index else None)
    geometry = static_geometry(world)
    for key, xy in (("start", tuple(world.start[:2])), ("goal", tuple(world.goal))):
        line = index.line_of((key,)) if index else None
        if not (0.0 < xy[0] < sx and 0.0 < xy[1] < sy):
            raise SpecError(
                f"({xy[0]:g}, {xy[1]:g}) lies outside the world [0, {sx:g}] x [0, {sy:g}]",
                file=file, key_path=key, line=line)
        hit = obstacle_containing(geometry, xy)
        if hit is not None:
            what = "a boundary wall" if hit < 0 else format_key_path(("obstacles", hit))
            raise SpecError(f"({xy[0]:g}, {xy[1]:g}) lies inside {what}; expected a free point",
                            file=file, key_path=key, line=line)
    check_goal_distance(world, GOAL_TOLERANCE_M, file=file, index=index)
    for i, mover in enumerate(world.movers):
        for j, (x, y) in enumerate(mover.path):
            if not (0.0 <= x <= sx and 0.0 <= y <= sy):
                loc = ("movers", i, "path", j)
                raise SpecError(f"waypoint ({x:g}, {y:g}) lies outside the world",
                                file=file, key_path=format_key_path(loc),
                                line=index.line_of(loc) if index else None)
