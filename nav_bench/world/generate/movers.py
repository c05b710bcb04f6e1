"""Moving obstacles for any world: cylinders patrolling free straight paths.

:func:`add_movers` adds ``count`` movers to world data. Each mover is a cylinder of radius
``size`` that goes back and forth on a straight segment (``pingpong``) or round an
axis-aligned rectangle (``loop``) at a speed drawn from ``speed``, with a random phase so
movers are not synchronised. A path is accepted only if

* the whole swept path keeps ``size + 0.02`` m from the static geometry and the world edge,
* it keeps ``size + robot_radius + margin`` m from the start and the goal (a mover never
  sits on the robot at the start, nor parks on the goal),
* it keeps ``2 * size + 0.02`` m from the paths of the movers already placed (movers never
  meet each other).

``loop`` rectangles need open floor (a perfect maze has no loop to drive round); in
corridors use ``pingpong``. If ``count`` movers do not fit after 2000 random paths each,
an :class:`~nav_bench.errors.InputError` says so.

Movers do not change the static map, so the goal stays reachable on it; they can block a
corridor for a while, which is the point. Every generator takes the same thing as
settings: ``movers: N`` (with ``mover_speed``, ``mover_radius``, ``mover_mode``).
"""

from __future__ import annotations

import copy
import itertools
import math
import zlib
from typing import Any

import numpy as np

from nav_bench.errors import InputError
from nav_bench.world.generate.common import DECIMALS, DEFAULT_ROBOT_RADIUS, unit_vector
from nav_bench.world.geometry import StaticGeometry, clearance, static_geometry
from nav_bench.world.load import world_from_data

CLEAR = 0.02  # m, extra room between a mover and the static geometry, the edge, other movers
SAMPLE_STEP = 0.02  # m, spacing of the clearance checks along a path
MAX_TRIES = 2000  # random paths drawn per mover before giving up


def point_segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance (m) from points (K, 2) to the segment a-b."""
    p = np.asarray(p, dtype=float).reshape(-1, 2)
    ab = b - a
    denom = float(ab @ ab)
    u = np.zeros(len(p)) if denom == 0 else np.clip((p - a) @ ab / denom, 0.0, 1.0)
    closest = a + u[:, None] * ab
    return np.hypot(*(p - closest).T)


def _cross(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))


def segment_distance(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> float:
    """Distance (m) between segments a-b and c-d (0 when they cross)."""
    d1, d2 = _cross(c, d, a), _cross(c, d, b)
    d3, d4 = _cross(a, b, c), _cross(a, b, d)
    if ((d1 > 0) != (d2 > 0)) and ((d3 > 0) != (d4 > 0)) and 0 not in (d1, d2, d3, d4):
        return 0.0
    return float(min(point_segment_distance(np.array([a, b]), c, d).min(),
                     point_segment_distance(np.array([c, d]), a, b).min()))


def _edges(path: np.ndarray, mode: str) -> list[tuple[np.ndarray, np.ndarray]]:
    pts = list(path) + ([path[0]] if mode == "loop" else [])
    return list(itertools.pairwise(pts))


def _sample_path(rng: np.random.Generator, size: tuple[float, float], inset: float,
                 length: tuple[float, float], mode: str) -> np.ndarray:
    sx, sy = size
    if mode == "loop":  # rectangle with sides drawn from `length` / 2
        w, h = rng.uniform(length[0] / 2, length[1] / 2, 2)
        x0 = rng.uniform(inset, max(inset, sx - inset - w))
        y0 = rng.uniform(inset, max(inset, sy - inset - h))
        path = np.array([[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h]])
    else:
        p0 = rng.uniform([inset, inset], [sx - inset, sy - inset])
        path = np.array([p0, p0 + rng.uniform(*length) * unit_vector(rng)])
    return np.round(path, DECIMALS)


def _path_ok(path: np.ndarray, mode: str, geometry: StaticGeometry, world_size: tuple[float, float],
             radius: float, keep_clear: list[tuple[np.ndarray, float]],
             others: list[np.ndarray], other_mode: list[str]) -> bool:
    sx, sy = world_size
    inset = radius + CLEAR
    if (path[:, 0] < inset).any() or (path[:, 0] > sx - inset).any() \
            or (path[:, 1] < inset).any() or (path[:, 1] > sy - inset).any():
        return False
    edges = _edges(path, mode)
    for a, b in edges:
        for point, dist in keep_clear:
            if point_segment_distance(point[None], a, b)[0] < dist:
                return False
    if clearance(geometry, path).min() < radius + CLEAR:  # cheap first look: the corners
        return False
    for other, omode in zip(others, other_mode, strict=True):
        for a, b in edges:
            for c, d in _edges(other, omode):
                if segment_distance(a, b, c, d) < 2 * radius + CLEAR:
                    return False
    samples = []
    for a, b in edges:
        n = max(2, math.ceil(float(np.hypot(*(b - a))) / SAMPLE_STEP) + 1)
        samples.append(a + np.linspace(0.0, 1.0, n)[:, None] * (b - a))
    return bool(clearance(geometry, np.vstack(samples)).min() >= radius + CLEAR)


def place_movers(rng: np.random.Generator, world_data: dict[str, Any], count: int,
                 speed: tuple[float, float], size: float, mode: str,
                 length: tuple[float, float] = (1.5, 4.0), robot_radius: float = DEFAULT_ROBOT_RADIUS,
                 margin: float = 0.5) -> list[dict[str, Any]]:
    """``count`` mover entries (world-YAML ``movers`` items) for ``world_data``, drawn with ``rng``.

    Raises :class:`InputError` when fewer than ``count`` fit (the world is too cluttered for
    movers of this size).
    """
    world = world_from_data(world_data)
    geometry = static_geometry(world)
    keep_clear = [(np.asarray(world.start[:2], dtype=float), size + robot_radius + margin),
                  (np.asarray(world.goal, dtype=float), size + robot_radius + margin)]
    # movers already in the world are avoided like the new ones
    paths = [np.asarray(m.path, dtype=float) for m in world.movers]
    modes = [m.mode for m in world.movers]
    movers = []
    for k in range(count):
        for _ in range(MAX_TRIES):
            path = _sample_path(rng, world.size, size + CLEAR, length, mode)
            if _path_ok(path, mode, geometry, world.size, size, keep_clear, paths, modes):
                break
        else:
            raise InputError(f"could place only {k} of {count} movers of radius {size:g} m on "
                             f"free paths clear of the start and goal; ask for fewer or smaller movers")
        paths.append(path)
        modes.append(mode)
        v = max(0.001, round(float(rng.uniform(*speed)), DECIMALS))
        travel = sum(math.sqrt(float((b - a) @ (b - a))) for a, b in _edges(path, mode))
        period = (travel if mode == "loop" else 2 * travel) / v
        movers.append({
            "shape": {"cylinder": {"radius": size}},
            "path": path.tolist(),
            "speed": v,
            "mode": mode,
            "phase_s": round(float(rng.uniform(0.0, period)), 2),
        })
    return movers


def add_movers(world_data: dict[str, Any], seed: int, count: int,
               speed: tuple[float, float] = (0.2, 0.5), size: float = 0.2,
               mode: str = "pingpong", *, length: tuple[float, float] = (1.5, 4.0),
               robot_radius: float = DEFAULT_ROBOT_RADIUS, margin: float = 0.5) -> dict[str, Any]:
    """A copy of ``world_data`` with ``count`` movers appended (see the module docstring).

    Args:
        world_data: plain world data (as loaded from YAML or made by a generator).
        seed: seeds the placement (same inputs -> same movers).
        count: movers to add (>= 0).
        speed: (low, high) m/s range of speeds. size: mover radius, m.
        mode: ``pingpong`` or ``loop``. length: (low, high) m, segment length or rectangle
            perimeter / 2. robot_radius, margin: m, paths keep ``size + robot_radius + margin``
            from the start and the goal.
    Returns:
        new world data; ``meta.movers`` records the arguments.
    """
    if mode not in ("pingpong", "loop"):
        raise InputError(f"mover mode must be 'pingpong' or 'loop', got {mode!r}")
    if count < 0 or size <= 0 or not 0 < speed[0] <= speed[1] or not 0 < length[0] <= length[1]:
        raise InputError("add_movers needs count >= 0, size > 0, 0 < speed low <= high "
                         "and 0 < length low <= high")
    rng = np.random.default_rng(np.random.SeedSequence([seed, zlib.crc32(b"movers")]))
    out = copy.deepcopy(world_data)
    out["movers"] = list(out.get("movers") or []) + place_movers(
        rng, world_data, count, speed, size, mode, length, robot_radius, margin)
    out.setdefault("meta", {})["movers"] = {
        "seed": seed, "count": count, "speed": list(speed), "size": size, "mode": mode,
        "length": list(length)}
    return out
