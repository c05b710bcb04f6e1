"""Load a world: the file's schema (:class:`~nav_bench.specs.WorldSpec`), then its geometry
(start and goal free and inside, movers inside)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from nav_bench.specs import WorldSpec
from nav_bench.world.geometry import check_world_geometry
from nav_bench.yamlio import LineIndex, load_yaml, validate


def world_from_data(data: Any, *, file: str | Path | None = None,
                    index: LineIndex | None = None, name: str | None = None) -> WorldSpec:
    """Validate already-parsed world data (structure, then geometry)."""
    world = validate(WorldSpec, data, file=file, index=index)
    if world.name is None:
        world = world.model_copy(update={"name": name or (Path(file).stem if file else "world")})
    check_world_geometry(world, file=file, index=index)
    return world


def load_world(path: str | Path) -> WorldSpec:
    """Read, validate and return the world in ``path``; name defaults to the file's stem."""
    data, index = load_yaml(path)
    return world_from_data(data, file=path, index=index)
