"""``nav-bench validate``: check world, planner-set, robot and suite files without simulating."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from nav_bench.batch.suite import load_suite
from nav_bench.errors import InputError, SpecError
from nav_bench.planners.registry import load_planner_set
from nav_bench.specs import load_robot
from nav_bench.world.load import load_world
from nav_bench.yamlio import load_yaml

# the top-level key that tells a file's kind, checked in this order
KINDS: list[tuple[str, str, Callable[[Path], Any]]] = [
    ("worlds", "suite", load_suite),
    ("planner", "planner set", load_planner_set),
    ("urdf", "robot", load_robot),
    ("size", "world", load_world),
]


def file_kind(path: Path) -> tuple[str, Callable[[Path], Any]]:
    """Which kind of file ``path`` is, from its top-level keys (a world if nothing else fits)."""
    data, _ = load_yaml(path)
    if not isinstance(data, dict):
        raise SpecError("expected a mapping at the top level", file=path, line=1)
    for key, kind, loader in KINDS:
        if key in data:
            return kind, loader
    if path.parent.name == "robots":
        return "robot", load_robot
    return "world", load_world


def expand_paths(paths: list[Path]) -> list[Path]:
    """Files as given; folders become every ``*.yaml``/``*.yml`` below them, sorted."""
    out: list[Path] = []
    for p in paths:
        if p.is_dir():
            out += sorted(q for q in p.rglob("*") if q.suffix in (".yaml", ".yml"))
        else:
            out.append(p)
    return out


def validate_paths(paths: list[Path]) -> tuple[list[str], int]:
    """Validate every file; returns (one message per invalid file, number of files checked)."""
    problems: list[str] = []
    files = expand_paths(paths)
    for path in files:
        if not path.exists():
            problems.append(f"{path}: no such file")
            continue
        try:
            _, loader = file_kind(path)
            loader(path)
        except InputError as exc:
            problems.append(str(exc))
    return problems, len(files)
