"""Seeded world generators: families of worlds at scale (``nav-bench generate KIND``).

Every generator turns ``(seed, settings)`` into plain world data that validates with
:func:`nav_bench.world.load.world_from_data`, and **guarantees the goal is reachable** for a disc
robot of radius ``robot_radius`` (default: the default robot's, from its URDF): each layout is checked with
:func:`nav_bench.world.optimal.optimal_path` on the true map, and rejected layouts are redrawn
with derived seeds (attempt 1, 2, ...). ``meta.generator`` records the kind, the seed, the
attempt and derived seed actually used, and every setting (defaults included), so a file
says how to make it again.

Determinism: attempt ``a`` draws from ``default_rng(derived_seed)`` with ``derived_seed`` the
first 64-bit word of ``SeedSequence([seed, a, crc32(kind)])`` (both platform independent);
coordinates are rounded to millimetres and written in a fixed key order and float format,
so the same kind, seed and settings give byte-identical files (``tests/world/
test_generate.py`` regenerates the committed examples in ``worlds/generated/``). The only
results that could differ between maths libraries are sin/cos in the last bit, which
would change a placement only at an exact tie of a gap test.

Families (one module each; settings with defaults and units via :func:`list_generators`):

========== ==============================================================================
maze       grid mazes, recursive backtracker or Wilson, optional loops (``maze.py``)
barn       BARN-style cellular-automaton clutter (Perille et al. 2020) (``cellular.py``)
office     rooms joined by doors, furniture that never blocks a door (``office.py``)
clutter    random boxes and cylinders at a given area density (``clutter.py``)
long_wall  a long wall with the goal behind it, towards one end (``traps.py``)
u_trap     a U-shaped (concave) trap, optionally nested U's (``traps.py``)
comb       a row of dead-end bays opening towards the robot (``traps.py``)
========== ==============================================================================

Every family also takes ``movers: N`` to add moving obstacles (``movers.py``), which are
placed after the static layout is fixed, so ``movers`` never changes the static map.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from nav_bench.errors import InputError, SpecError, UnknownNameError
from nav_bench.world.generate import cellular, clutter, maze, office, traps
from nav_bench.world.generate.common import (
    GeneratorInfo,
    Setting,
    attempt_rng,
    clean_world_data,
    derived_seed,
    resolve_settings,
    world_yaml_text,
    write_world_yaml,
)
from nav_bench.world.generate.movers import add_movers, place_movers
from nav_bench.world.load import world_from_data
from nav_bench.world.optimal import optimal_path

__all__ = [
    "GeneratorInfo",
    "Setting",
    "add_movers",
    "generate_world",
    "list_generators",
    "world_yaml_text",
    "write_world_yaml",
]

_GENERATORS: tuple[GeneratorInfo, ...] = (
    maze.INFO,
    cellular.INFO,
    office.INFO,
    clutter.INFO,
    traps.LONG_WALL,
    traps.U_TRAP,
    traps.COMB,
)


def list_generators() -> dict[str, GeneratorInfo]:
    """Registered generators by name, each with its doc and settings (name, default, unit, doc)."""
    return {info.name: info for info in _GENERATORS}


def generate_world(kind: str, seed: int = 0, settings: dict[str, Any] | None = None) -> dict[str, Any]:
    """World data from generator ``kind`` with ``seed`` and ``settings`` (missing ones default).

    Returns:
        plain data (dicts, lists, floats rounded to mm) that validates as a world, with
        ``meta.generator = {kind, seed, attempt, derived_seed, settings}``.
    Raises:
        UnknownNameError: ``kind`` is not registered (with a did-you-mean).
        InputError: an unknown setting, a value of the wrong type or range, a negative seed,
            or settings under which no reachable layout was found in ``max_attempts`` tries.
    """
    generators = list_generators()
    if kind not in generators:
        raise UnknownNameError("generator", kind, generators)
    info = generators[kind]
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"generator seed must be a whole number >= 0, got {seed!r}")
    seed = int(seed)
    s = resolve_settings(info, settings)

    reason = ""
    for attempt in range(s["max_attempts"]):
        rng = attempt_rng(kind, seed, attempt)
        data = clean_world_data(info.build(rng, s))
        try:
            world = world_from_data(data, name=kind)
        except SpecError as exc:  # e.g. furniture on the start: draw again
            reason = f"the layout was invalid ({exc.problem} at {exc.key_path})"
            continue
        if optimal_path(world, s["robot_radius"]).length_m is not None:
            break
        reason = f"the goal was unreachable for a robot of radius {s['robot_radius']:g} m"
    else:
        raise InputError(
            f"generator {kind!r} found no valid layout in {s['max_attempts']} attempts (seed "
            f"{seed}): {reason}. Loosen the settings (wider gaps, lower density) or raise "
            f"max_attempts.")
    if s["movers"]:
        mover_rng = attempt_rng("movers", derived_seed(kind, seed, attempt), 0)
        data["movers"] = clean_world_data({"m": place_movers(
            mover_rng, data, s["movers"], s["mover_speed"], s["mover_radius"], s["mover_mode"],
            s["mover_length"], robot_radius=s["robot_radius"])})["m"]
    data["meta"] = clean_world_data({"generator": {
        "kind": kind, "seed": seed, "attempt": attempt,
        "derived_seed": derived_seed(kind, seed, attempt), "settings": s}})
    return data
