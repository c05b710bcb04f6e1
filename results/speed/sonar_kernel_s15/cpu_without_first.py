"""Worker CPU of a bench_suite gate with and without each label's first episode per side.

The first episode of a label in a worker process pays one-off costs: on the ``before`` side
(a fresh checkout of the old revision, with no Numba cache) it compiles D* Lite's kernels
(~8-14 s CPU for dstar_lite and dwa_global); a tree with a warm cache only loads them. Leaving
the first episode out compares the steady state.

    python cpu_without_first.py GATE_FOLDER...   (each holding before.jsonl/after.jsonl or
                                                  before/episodes.jsonl, after/episodes.jsonl)
"""

from __future__ import annotations

import json
import sys
from pathlib import Path


def rows(folder: Path, side: str) -> list[dict]:
    path = folder / f"{side}.jsonl"
    if not path.exists():
        path = folder / side / "episodes.jsonl"
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def per_label(folder: Path, side: str) -> dict[str, list[float]]:
    """bench_cpu_s of each episode, in play order, by planner."""
    out: dict[str, list[float]] = {}
    for row in rows(folder, side):
        out.setdefault(row["planner"], []).append(row["bench_cpu_s"])
    return out


def main() -> None:
    for name in sys.argv[1:]:
        folder = Path(name)
        before, after = per_label(folder, "before"), per_label(folder, "after")
        all_b, all_a = (sum(map(sum, d.values())) for d in (before, after))
        rest_b, rest_a = (sum(sum(v[1:]) for v in d.values()) for d in (before, after))
        print(f"{folder}: all {all_b:.1f} -> {all_a:.1f} ({all_a / all_b:.3f}); without each "
              f"label's first episode {rest_b:.1f} -> {rest_a:.1f} ({rest_a / rest_b:.3f})")
        for label in before:
            b, a = before[label], after[label]
            print(f"  {label:12s} first {b[0]:6.2f} -> {a[0]:6.2f}   rest {sum(b[1:]):6.1f} -> "
                  f"{sum(a[1:]):6.1f} ({sum(a[1:]) / sum(b[1:]):.3f})")


if __name__ == "__main__":
    main()
