"""The families table's cells (README "Baselines on generated families") from result rows.

    python family_cells.py ROWS.jsonl [--label L]

Per family and in all: reached / episodes · SPL (mean) · timeouts (t) and stuck endings (s) ·
mean map precision (P) and recall (R) and the episodes with a phantom wall on the optimal route
(ph), for rows that carry map figures.
"""

from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path

FAMILIES = ("maze", "office", "clutter", "u_trap", "comb", "long_wall")


def cell(rows: list[dict]) -> str:
    """One cell of the table for ``rows`` (one planner, one family or all)."""
    reached = sum(r["outcome"] == "reached" for r in rows)
    timeouts = sum(r["outcome"] == "timeout" for r in rows)
    stuck = sum(r["outcome"] == "stuck" for r in rows)
    spl = statistics.fmean(r["spl"] for r in rows)
    text = f"{reached}/{len(rows)} · SPL {spl:.2f} · {timeouts}t {stuck}s"
    mapped = [r for r in rows if r.get("map_precision") is not None]
    if mapped:
        p = statistics.fmean(r["map_precision"] for r in mapped)
        rc = statistics.fmean(r["map_recall"] for r in mapped)
        ph = sum((r.get("map_phantom_cells") or 0) > 0 for r in mapped)
        text += f" · P {p:.2f} R {rc:.2f} ph {ph}"
    return text


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rows", type=Path)
    ap.add_argument("--label", help="only this planner label")
    args = ap.parse_args()
    rows = [json.loads(line) for line in args.rows.read_text().splitlines()]
    rows = [r for r in rows if not args.label or (r.get("label") or r["planner"]) == args.label]
    for family in FAMILIES:
        print(f"| {family} | {cell([r for r in rows if r['world'].rsplit('_', 1)[0] == family])} |")
    print(f"| all | {cell(rows)} |")


if __name__ == "__main__":
    main()
