"""A "no new ground" stuck rule replayed on stored traces: would it end looping robots early
without cutting an episode that went on to reach its goal?

    python no_new_ground.py FOLDER [FOLDER ...]

The rule: the episode ends ``stuck`` when the robot's true position has entered no cell it had
not visited before (square cells of ``CELL_SIZES`` m) for ``WINDOWS_S`` seconds. For every row
of each results folder whose trace exists, finds the times at which a new cell was first
entered; a reached episode with a gap of at least W before its end would have been cut, a
timeout whose gap reaches W ends W after the gap began. Only rows with ``stuck_s`` = 30 (the
default) count; identical episodes in several folders (same label, world, seed, outcome, time)
count once.
"""

from __future__ import annotations

import json
import sys
from collections import Counter
from pathlib import Path

import numpy as np

CELL_SIZES = (0.5, 1.0)  # m
WINDOWS_S = (90, 120, 150, 180, 210, 240)


def new_ground_times(t: np.ndarray, xy: np.ndarray, cell: float) -> np.ndarray:
    """Ascending times (s) at which a cell was first entered, then the trace's last time."""
    rc = np.floor(xy / cell).astype(np.int64)
    _, first = np.unique(rc[:, 0] * 1_000_003 + rc[:, 1], return_index=True)
    return np.append(np.sort(t[first]), t[-1])


def episodes(folders: list[Path]) -> list[dict]:
    """One record per distinct episode: label, outcome, time_s and its new-ground times."""
    seen, out = set(), []
    for folder in folders:
        table = folder / "episodes.jsonl"
        if not table.exists():
            continue
        for line in table.read_text().splitlines():
            try:
                row = json.loads(line)
            except ValueError:  # a line cut by an interrupted run
                continue
            trace = folder / (row.get("trace") or f"traces/{row.get('job_id')}.npz")
            if (row.get("settings") or {}).get("stuck_s") != 30.0 or not trace.exists():
                continue
            key = (row["label"], row["world"], row["seed"], row["outcome"], row["time_s"])
            if key in seen:
                continue
            seen.add(key)
            with np.load(trace) as data:
                t, xy = data["t"].astype(float), data["true_pose"][:, :2].astype(float)
            out.append({"label": row["label"], "outcome": row["outcome"], "time_s": row["time_s"],
                        "new": {c: new_ground_times(t, xy, c) for c in CELL_SIZES}})
    return out


def main() -> None:
    eps = episodes([Path(p) for p in sys.argv[1:]])
    print("distinct episodes", len(eps), dict(Counter(e["outcome"] for e in eps)))
    for cell in CELL_SIZES:
        print(f"cell {cell} m")
        for window in WINDOWS_S:
            cut, ended, saved = Counter(), 0, 0.0
            for e in eps:
                times = e["new"][cell]
                late = np.nonzero(np.diff(times) >= window)[0]
                if not len(late):
                    continue
                fire = times[late[0]] + window
                if e["outcome"] == "reached":
                    cut[e["label"]] += 1
                elif e["outcome"] == "timeout" and fire < e["time_s"] - 1e-6:
                    ended += 1
                    saved += e["time_s"] - fire
            print(f"  W={window:3d} s: reached episodes cut {sum(cut.values()):3d} "
                  f"{dict(cut.most_common(4))}; timeouts ended {ended}, simulated s saved {saved:.0f}")


if __name__ == "__main__":
    main()
