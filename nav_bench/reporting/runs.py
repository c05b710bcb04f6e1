"""What a report reads: results folders (their rows and run metadata), traces and worlds."""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from nav_bench.batch.store import ResultsStore
from nav_bench.episode import read_trace_positions, read_trace_world
from nav_bench.errors import InputError
from nav_bench.paths import project_file
from nav_bench.specs import WorldSpec
from nav_bench.world.load import load_world


@dataclass
class Run:
    """One results folder."""

    name: str
    folder: Path
    meta: dict[str, Any]
    rows: list[dict[str, Any]]

def load_runs(dirs: Sequence[Path]) -> list[Run]:
    """The runs in ``dirs``; each row gets ``run`` (folder name) and ``set`` (its group label)."""
    if not dirs:
        raise InputError("report needs at least one results folder")
    runs: list[Run] = []
    names: Counter[str] = Counter()
    for d in dirs:
        store = ResultsStore(d)
        if not store.episodes_path.exists() and not store.run_path.exists():
            raise InputError(f"{d} is not a nav-bench results folder (no episodes.jsonl or "
                             f"run.json)")
        meta = store.read_run() if store.run_path.exists() else {}
        name = Path(d).resolve().name
        names[name] += 1
        if names[name] > 1:
            name = f"{name}#{names[name]}"
        rows = store.checked_rows()  # a row a report cannot read is named, not guessed at
        for r in rows:
            r["run"] = name
            r.setdefault("label", r.get("planner", "?"))
        runs.append(Run(name, Path(d), meta, rows))
    several = len(runs) > 1
    for run in runs:
        for r in run.rows:
            r["set"] = f"{run.name}/{r['label']}" if several else r["label"]
    return runs


def trace_path(run: Run, row: dict[str, Any]) -> Path:
    """Where a row's trace lies in its results folder."""
    rel = row.get("trace") or f"traces/{row.get('job_id')}.npz"
    return run.folder / rel


def load_trajectory(path: Path) -> np.ndarray | None:
    """(T, 2) true positions from a stored trace, or None if it is missing or unreadable."""
    try:
        return read_trace_positions(path)
    except (OSError, KeyError, ValueError):
        return None


def world_of(rows: Sequence[dict[str, Any]], runs: Sequence[Run]) -> WorldSpec | None:
    """The true map of the rows' world: from a stored trace, else from the row's world_file."""
    by_name = {run.name: run for run in runs}
    for row in rows:
        run = by_name[row["run"]]
        try:
            return read_trace_world(trace_path(run, row))
        except Exception:  # no trace, an older format: try the world file
            continue
    for row in rows:
        run = by_name[row["run"]]
        file = row.get("world_file")
        if not file:
            continue
        cwd = Path((run.meta.get("suite") or {}).get("cwd") or ".")
        for candidate in (Path(file), cwd / file, project_file(file)):
            if candidate.is_file():
                try:
                    return load_world(candidate)
                except Exception:
                    break
    return None
