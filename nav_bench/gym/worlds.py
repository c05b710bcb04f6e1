"""The worlds a Gymnasium environment samples from: files, globs, generator families."""

from __future__ import annotations

import glob
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from nav_bench.errors import InputError
from nav_bench.paths import find, project_roots
from nav_bench.specs import WorldSpec
from nav_bench.world.load import load_world, world_from_data

_GLOB = set("*?[")


@dataclass
class Family:
    """A generator family: ``{generate: KIND, seeds: "0..999", set: {...}}``; one world per
    sampled seed, made when first drawn."""

    kind: str
    seeds: list[int]
    settings: dict[str, Any]
    name: str
    cache: dict[int, WorldSpec] = field(default_factory=dict)

    def world(self, seed: int) -> WorldSpec:
        if seed not in self.cache:
            from nav_bench.world.generate import generate_world

            data = generate_world(self.kind, seed, dict(self.settings))
            self.cache[seed] = world_from_data({**data, "name": f"{self.name}_{seed}"})
        return self.cache[seed]


@dataclass
class WorldPool:
    """Fixed worlds (with the file each came from) and generator families, sampled uniformly:
    first a source (each file counts one, each family one), then a seed of the family."""

    fixed: list[tuple[WorldSpec, str | None]]
    families: list[Family]

    def sample(self, rng: np.random.Generator) -> tuple[WorldSpec, str | None]:
        k = int(rng.integers(len(self.fixed) + len(self.families)))
        if k < len(self.fixed):
            return self.fixed[k]
        family = self.families[k - len(self.fixed)]
        return family.world(family.seeds[int(rng.integers(len(family.seeds)))]), None

    def __len__(self) -> int:
        return len(self.fixed) + sum(len(f.seeds) for f in self.families)


def world_pool(spec: Any) -> WorldPool:
    """A pool from a world (a :class:`WorldSpec`, a file or shipped name, a glob, a generator
    family dict) or a list of them."""
    from nav_bench.batch.suite import parse_seeds

    items = spec if isinstance(spec, list | tuple) else [spec]
    fixed: list[tuple[WorldSpec, str | None]] = []
    families: list[Family] = []
    for item in items:
        if isinstance(item, WorldSpec):
            fixed.append((item, None))
        elif isinstance(item, dict):
            unknown = set(item) - {"generate", "seeds", "set", "name"}
            if "generate" not in item or unknown:
                raise InputError(f"a world family is {{generate: KIND, seeds: ..., set: {{...}}}}, "
                                 f"got {item!r}")
            seeds = parse_seeds(item.get("seeds", "0..9999"))
            kind = str(item["generate"])
            families.append(Family(kind, seeds, dict(item.get("set") or {}),
                                   str(item.get("name") or kind)))
        elif isinstance(item, str | Path) and _GLOB & set(str(item)):
            fixed += [(load_world(p), given) for p, given in _glob(str(item))]
        elif isinstance(item, str | Path):
            found = find("world", item)
            fixed.append((load_world(found.path), found.given))
        else:
            raise InputError(f"a world is a file, a name, a glob or a generator family, "
                             f"got {item!r}")
    if not fixed and not families:
        raise InputError(f"no worlds in {spec!r}")
    return WorldPool(fixed, families)


def _glob(pattern: str) -> list[tuple[Path, str]]:
    if Path(pattern).is_absolute():
        return [(Path(p), p) for p in sorted(glob.glob(pattern, recursive=True))]
    for root in project_roots():
        hits = sorted(glob.glob(pattern, root_dir=root, recursive=True))
        if hits:
            return [(root / h, h) for h in hits]
    raise InputError(f"world glob {pattern!r} matches no file")
