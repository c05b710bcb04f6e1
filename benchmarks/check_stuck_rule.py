"""The stuck rule replayed on stored traces: which episodes it would end earlier, and when.

    python benchmarks/check_stuck_rule.py RESULTS_DIR [RESULTS_DIR ...] [--area-radius 0.6]
                                          [--list]

For every row with a trace, plays the true positions through
:class:`nav_bench.episode.ending.Stuck` with the row's own ``stuck_s`` and ``stuck_radius`` and
the area rule of radius ``--area-radius`` (m; window 3 x stuck_s), and reports per outcome how
many episodes it would have ended before they ended: a reached episode cut is a rule that stops
real progress (must be 0); timeouts that become ``stuck`` and the simulated seconds they no
longer play are what the rule saves. ``--list`` names every episode that changes. The traces
hold one sample per control cycle, as the episode checks its endings.
"""

from __future__ import annotations

import argparse
import json
from collections import defaultdict
from pathlib import Path

import numpy as np

from nav_bench.episode.ending import AREA_WINDOW, DEFAULT_AREA_RADIUS, Stuck


def fire_time(t: np.ndarray, xy: np.ndarray, stuck_s: float, radius: float,
              area_radius: float | None) -> tuple[float | None, str | None]:
    """When ``Stuck`` would end the episode (s), and which of its rules, or (None, None)."""
    stuck = Stuck(stuck_s, radius, xy[0], area_radius=area_radius)
    for ti, p in zip(t, xy, strict=True):
        if stuck(float(ti), p):
            return float(ti), stuck.fired
    return None, None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folders", nargs="+", type=Path)
    ap.add_argument("--area-radius", type=float, default=DEFAULT_AREA_RADIUS)
    ap.add_argument("--list", action="store_true", help="name every episode that changes")
    args = ap.parse_args()
    counts: dict[str, list] = defaultdict(lambda: [0, 0, 0.0])  # outcome: n, ended earlier, s saved
    changed = []
    for folder in args.folders:
        for line in (folder / "episodes.jsonl").read_text().splitlines():
            row = json.loads(line)
            settings = row.get("settings") or {}
            if not row.get("trace") or settings.get("stuck_s") is None:
                continue
            with np.load(folder / row["trace"]) as data:
                t, xy = data["t"], data["true_pose"][:, :2].astype(float)
            fired, rule = fire_time(t, xy, settings["stuck_s"], settings.get("stuck_radius", 0.2),
                                    args.area_radius)
            c = counts[row["outcome"]]
            c[0] += 1
            if fired is not None and fired < row["time_s"] - 1e-6:
                c[1] += 1
                c[2] += row["time_s"] - fired
                changed.append((folder.name, row["label"], row["world"], row["seed"],
                                row["outcome"], row["time_s"], fired, rule))
    window = f"{AREA_WINDOW:g} x stuck_s"
    print(f"area rule: positions of the last {window} within a disc of {args.area_radius:g} m")
    print(f"{'outcome':8s} {'episodes':>8s} {'ended earlier':>13s} {'sim s saved':>11s}")
    for outcome, (n, earlier, saved) in sorted(counts.items()):
        print(f"{outcome:8s} {n:8d} {earlier:13d} {saved:11.0f}")
    if args.list:
        for folder, label, world, seed, outcome, time_s, fired, rule in changed:
            print(f"  {folder}: {label} {world} seed {seed}: {outcome} at {time_s:g} s -> "
                  f"stuck at {fired:g} s ({rule} rule)")


if __name__ == "__main__":
    main()
