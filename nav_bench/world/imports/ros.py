"""Import a ROS ``map_server`` map (PGM/PNG image + YAML) as a world.

The occupancy of a pixel follows map_server's trinary mode: with ``negate: 0``,
``p = (255 - value) / 255``; ``p > occupied_thresh`` is occupied, ``p < free_thresh`` free,
anything between unknown (``negate: 1`` uses ``p = value / 255``). The image's first row is
the top of the map (largest y).

Conversion choices (recorded in the world's ``meta``):

* **Crop.** ROS maps carry wide unknown borders; the world is the bounding box of the
  *known* (free or occupied) pixels grown by ``crop_margin_m``.
* **Frame.** The world frame has its origin at the lower-left corner of the cropped map, so
  a map-frame point ``p`` maps to ``R(-yaw) (p - origin) - crop_offset``; ``meta`` keeps the
  map's ``origin`` and the crop offset so results can be mapped back.
* **Unknown** pixels are obstacles (default) or free (``unknown_as="free"``).
* **Obstacles.** Blocked pixels are merged into few axis-aligned boxes
  (:func:`~nav_bench.world.imports.rectangles.merge_cells`); pockets of free pixels that are
  not 8-connected to the start's or goal's free region are filled (they cannot be reached
  or seen and would only add boxes).
* **Start and goal** are given in the map frame, as a ROS user would; without them the
  importer picks a far-apart pair (:func:`~nav_bench.world.imports.grid.pick_endpoints`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Literal

import numpy as np
from scipy import ndimage

from nav_bench.errors import InputError, SpecError
from nav_bench.world.imports.grid import EIGHT, blocked_to_boxes, pick_endpoints, q, world_skeleton
from nav_bench.yamlio import load_yaml

FREE, OCCUPIED, UNKNOWN = 0, 1, 2


# --------------------------------------------------------------------------- images
def _pgm_tokens(raw: bytes, count: int) -> tuple[list[bytes], int]:
    """The first ``count`` header tokens of a PNM file (comments skipped) and the offset after."""
    tokens: list[bytes] = []
    i, n = 0, len(raw)
    while len(tokens) < count:
        while i < n and raw[i:i + 1].isspace():
            i += 1
        if i < n and raw[i:i + 1] == b"#":
            while i < n and raw[i:i + 1] not in (b"\n", b"\r"):
                i += 1
            continue
        j = i
        while j < n and not raw[j:j + 1].isspace() and raw[j:j + 1] != b"#":
            j += 1
        if j == i:
            raise ValueError("truncated header")
        tokens.append(raw[i:j])
        i = j
    return tokens, i + 1  # exactly one whitespace byte follows the last header token


def read_pgm(path: str | Path) -> np.ndarray:
    """A binary (P5) or ASCII (P2) PGM as a (H, W) uint8 array, first row = top of the image.

    16-bit images (maxval > 255) are scaled to 0..255.
    """
    path = Path(path)
    raw = path.read_bytes()
    try:
        (magic, w, h, maxval), offset = _pgm_tokens(raw, 4)
        width, height, top = int(w), int(h), int(maxval)
        if magic == b"P5":
            dtype = np.dtype(">u2") if top > 255 else np.dtype(np.uint8)
            data = np.frombuffer(raw, dtype=dtype, count=width * height, offset=offset)
        elif magic == b"P2":
            data = np.array(raw[offset:].split()[:width * height], dtype=np.int64)
        else:
            raise ValueError(f"magic number {magic!r} is not P5 or P2")
        if data.size != width * height:
            raise ValueError(f"expected {width}x{height} pixels, found {data.size}")
    except ValueError as exc:
        raise InputError(f"{path}: not a readable PGM image ({exc})") from None
    img = data.reshape(height, width).astype(np.float64)
    if top != 255:
        img = np.round(img * (255.0 / top))
    return img.astype(np.uint8)


def read_map_image(path: str | Path) -> np.ndarray:
    """(H, W) uint8 grey values of a map image (PGM/PNM natively, PNG via matplotlib).

    Colour images are averaged over their colour channels (alpha ignored), as map_server does.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: map image not found")
    suffix = path.suffix.lower()
    if suffix in (".pgm", ".pnm"):
        return read_pgm(path)
    if suffix == ".png":
        import matplotlib.image as mpimg

        img = np.asarray(mpimg.imread(path), dtype=np.float64)  # PNG: floats in [0, 1]
        if img.ndim == 3:
            img = img[..., :3].mean(axis=2) if img.shape[2] >= 3 else img[..., 0]
        return np.round(img * 255.0).astype(np.uint8)
    raise InputError(f"{path}: unsupported map image format {suffix!r} (use PGM or PNG)")


def classify(image: np.ndarray, negate: bool, occupied_thresh: float, free_thresh: float,
             mode: str = "trinary") -> np.ndarray:
    """(H, W) uint8 of FREE / OCCUPIED / UNKNOWN per pixel, map_server's rules."""
    v = image.astype(np.float64)
    if mode == "raw":  # values are occupancy percentages; > 100 (e.g. 255) unknown
        p = v / 100.0
        out = np.where(p > occupied_thresh, OCCUPIED, np.where(p < free_thresh, FREE, UNKNOWN))
        out[v > 100] = UNKNOWN
        return out.astype(np.uint8)
    p = v / 255.0 if negate else (255.0 - v) / 255.0
    return np.where(p > occupied_thresh, OCCUPIED,
                    np.where(p < free_thresh, FREE, UNKNOWN)).astype(np.uint8)


# --------------------------------------------------------------------------- map yaml
def _read_map_yaml(map_yaml: Path) -> dict[str, Any]:
    data, index = load_yaml(map_yaml)
    if not isinstance(data, dict):
        raise SpecError("expected a ROS map YAML mapping (image, resolution, origin, ...)",
                        file=map_yaml, line=1)

    def fail(key: str, problem: str) -> SpecError:
        return SpecError(problem, file=map_yaml, key_path=key, line=index.line_of((key,)))

    for key in ("image", "resolution", "origin"):
        if key not in data:
            raise fail(key, f"missing key {key!r} (a ROS map_server YAML needs image, resolution, origin)")
    try:
        res = float(data["resolution"])
    except (TypeError, ValueError):
        raise fail("resolution", f"expected a number of metres per pixel, got {data['resolution']!r}") from None
    if not res > 0:
        raise fail("resolution", f"expected a positive number of metres per pixel, got {res:g}")
    origin = data["origin"]
    if not (isinstance(origin, list) and len(origin) in (2, 3)
            and all(isinstance(v, (int, float)) for v in origin)):
        raise fail("origin", f"expected [x, y, yaw] numbers, got {origin!r}")
    origin = [float(v) for v in origin] + [0.0] * (3 - len(origin))
    out = {"image": str(data["image"]), "resolution": res, "origin": origin,
           "negate": bool(int(data.get("negate", 0))),
           "occupied_thresh": float(data.get("occupied_thresh", 0.65)),
           "free_thresh": float(data.get("free_thresh", 0.196)),
           "mode": str(data.get("mode", "trinary"))}
    if out["mode"] not in ("trinary", "scale", "raw"):
        raise fail("mode", f"unknown mode {out['mode']!r}; expected trinary, scale or raw")
    if not 0.0 <= out["free_thresh"] <= out["occupied_thresh"] <= 1.0:
        raise fail("free_thresh", "expected 0 <= free_thresh <= occupied_thresh <= 1")
    return out


def _cell_of(world_xy: tuple[float, float], res: float, shape: tuple[int, int]) -> tuple[int, int] | None:
    r, c = math.floor(world_xy[1] / res), math.floor(world_xy[0] / res)
    return (r, c) if 0 <= r < shape[0] and 0 <= c < shape[1] else None


def import_ros(map_yaml: str | Path, start: tuple[float, float] | None = None,
               goal: tuple[float, float] | None = None,
               unknown_as: Literal["obstacle", "free"] = "obstacle", *,
               crop_margin_m: float = 0.1, robot_radius: float | None = None,
               name: str | None = None, source: str | None = None,
               licence: str | None = None) -> dict[str, Any]:
    """A ROS map_server map as world data (a dict ready for ``world_from_data``).

    Args:
        map_yaml: the map's YAML file; its ``image`` is relative to it.
        start, goal: (x, y) in the map frame (m); ``None`` picks a far-apart pair.
        unknown_as: how unknown pixels are treated.
        crop_margin_m: margin kept around the known pixels (m).
        robot_radius: disc radius used to pick start/goal automatically (m); default: the
            default robot's.
        name: world name (default: the YAML file's stem; ``map`` takes its folder's name).
        source, licence: attribution kept in ``meta`` (where the map comes from, its licence).
    Raises:
        InputError / SpecError: unreadable or invalid files, start/goal outside or blocked.
    """
    map_yaml = Path(map_yaml)
    if not map_yaml.is_file():
        raise InputError(f"{map_yaml}: ROS map YAML not found")
    if unknown_as not in ("obstacle", "free"):
        raise InputError(f"unknown_as must be 'obstacle' or 'free', got {unknown_as!r}")
    cfg = _read_map_yaml(map_yaml)
    image_path = (map_yaml.parent / cfg["image"]).resolve()
    cls = classify(read_map_image(image_path), cfg["negate"], cfg["occupied_thresh"],
                   cfg["free_thresh"], cfg["mode"])[::-1]  # row 0 = bottom (lowest y)
    res = cfg["resolution"]
    known = cls != UNKNOWN
    if not known.any():
        raise InputError(f"{image_path}: the map has no known (free or occupied) pixel")
    rows, cols = np.flatnonzero(known.any(axis=1)), np.flatnonzero(known.any(axis=0))
    m = round(crop_margin_m / res)
    r0, r1 = max(0, int(rows[0]) - m), min(cls.shape[0], rows[-1] + 1 + m)
    c0, c1 = max(0, int(cols[0]) - m), min(cls.shape[1], cols[-1] + 1 + m)
    cls = cls[r0:r1, c0:c1]
    blocked = (cls == OCCUPIED) | ((cls == UNKNOWN) & (unknown_as == "obstacle"))
    h, w = blocked.shape
    size = (w * res, h * res)

    ox, oy, yaw = cfg["origin"]
    cy, sy_ = math.cos(yaw), math.sin(yaw)

    def to_world(p: tuple[float, float], what: str) -> tuple[float, float]:
        dx, dy = float(p[0]) - ox, float(p[1]) - oy
        x, y = cy * dx + sy_ * dy - c0 * res, -sy_ * dx + cy * dy - r0 * res
        cell = _cell_of((x, y), res, blocked.shape)
        if cell is None:
            raise InputError(f"{what} ({p[0]:g}, {p[1]:g}) in the map frame lies outside the "
                             f"imported area of {map_yaml} (known pixels plus margin)")
        if blocked[cell]:
            kind = "an occupied" if cls[cell] == OCCUPIED else "an unknown"
            raise InputError(f"{what} ({p[0]:g}, {p[1]:g}) in the map frame lies in {kind} "
                             f"pixel of {map_yaml}; expected a free point")
        return q(x), q(y)

    start_w = to_world(start, "start") if start is not None else None
    goal_w = to_world(goal, "goal") if goal is not None else None
    blocked = _fill_pockets(blocked, [p for p in (start_w, goal_w) if p is not None], res)

    obstacles = blocked_to_boxes(blocked, res)
    skeleton = world_skeleton(size, obstacles)
    if start_w is None and goal_w is None:
        start_w, goal_w = pick_endpoints(skeleton, robot_radius)
    elif goal_w is None:
        start_w, goal_w = pick_endpoints(skeleton, robot_radius, fixed=start_w)
    elif start_w is None:
        goal_w, start_w = pick_endpoints(skeleton, robot_radius, fixed=goal_w)
    stem = map_yaml.stem if map_yaml.stem != "map" else map_yaml.parent.name
    return {
        "name": name or stem,
        "description": (f"ROS map {map_yaml.name} ({cls.shape[1]}x{cls.shape[0]} px of {res:g} m "
                        f"after cropping), imported"),
        "size": [q(size[0]), q(size[1])],
        "boundary": True,
        "start": [start_w[0], start_w[1]],
        "goal": [goal_w[0], goal_w[1]],
        "obstacles": obstacles,
        "meta": {
            "source": source or f"ROS map_server map {map_yaml.name} (image {Path(cfg['image']).name})",
            "licence": licence or "unknown (state the map's licence with --licence)",
            "imported_by": "nav-bench import ros",
            "resolution_m": res,
            "ros_origin": [q(ox), q(oy), q(yaw)],
            "crop_offset_px": [int(c0), int(r0)],  # col, row (from the bottom) of the world origin
            "map_frame_of_world_origin": [q(ox + cy * c0 * res - sy_ * r0 * res),
                                          q(oy + sy_ * c0 * res + cy * r0 * res)],
            "pixels": [int(w), int(h)],
            "unknown_as": unknown_as,
            "start_goal": "given (map frame)" if start is not None and goal is not None else "automatic",
        },
    }


def _fill_pockets(blocked: np.ndarray, keep_xy: list[tuple[float, float]], res: float) -> np.ndarray:
    """Fill free regions (8-connected) other than those holding ``keep_xy`` points, or other
    than the largest one when no point is given."""
    labels, count = ndimage.label(~blocked, structure=EIGHT)
    if count <= 1:
        return blocked
    keep = {int(labels[_cell_of(p, res, blocked.shape)]) for p in keep_xy}  # type: ignore[index]
    if not keep_xy:
        sizes = np.bincount(labels.ravel())
        sizes[0] = 0
        keep = {int(np.argmax(sizes))}
    return ~np.isin(labels, sorted(keep))
