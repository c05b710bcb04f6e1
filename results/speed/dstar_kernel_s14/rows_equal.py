"""Are two episodes.jsonl files the same rows? Pairs by (label, world, seed) and compares the
fields that say what happened (exactly, floats bit for bit), the ids, and the planner's
recorded events and map figures.

    python rows_equal.py BEFORE.jsonl AFTER.jsonl

Prints the pairs, the pairs that differ (with the fields) and exits 1 if any differ.
"""

from __future__ import annotations

import json
import sys

FIELDS = ("outcome", "time_s", "path_length_m", "collisions", "min_clearance_m", "success", "spl",
          "replans", "goal_distance_m", "time_near_obstacles_s", "events", "map_precision",
          "map_recall", "map_observed_cells", "map_occupied_cells", "job_id", "params_id")


def rows(path: str) -> dict[tuple[str, str, int], dict]:
    with open(path) as f:
        return {(r["label"], r["world"], r["seed"]): r for r in map(json.loads, f)}


def main() -> None:
    before, after = rows(sys.argv[1]), rows(sys.argv[2])
    keys = sorted(set(before) & set(after))
    differ = []
    for k in keys:
        fields = [f for f in FIELDS if before[k].get(f) != after[k].get(f)]
        if fields:
            differ.append((k, fields))
    only = sorted(set(before) ^ set(after))
    print(f"{len(keys)} pairs, {len(differ)} differ, {len(only)} unpaired; fields: {', '.join(FIELDS)}")
    for k, fields in differ:
        print(f"  {k}: {fields}")
    sys.exit(1 if differ or only else 0)


if __name__ == "__main__":
    main()
