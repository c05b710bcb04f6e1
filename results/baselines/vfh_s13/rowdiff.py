"""Rows of two episodes.jsonl files that differ in outcome, time, path length, contacts,
minimum clearance or events, matched by (label, world, seed).

python results/baselines/vfh_s13/rowdiff.py BEFORE.jsonl AFTER.jsonl
"""
import json
import sys

KEYS = ("outcome", "time_s", "path_length_m", "collisions", "min_clearance_m", "events")


def load(path: str) -> dict:
    with open(path) as fh:
        return {(r["label"], r["world"], r["seed"]): r for r in map(json.loads, fh)}


before, after = load(sys.argv[1]), load(sys.argv[2])
diff = [k for k in before if any(before[k][f] != after[k][f] for f in KEYS)]
print(f"{len(before)} / {len(after)} rows; {len(diff)} differ in {KEYS}")
for k in diff:
    print(k, [(f, before[k][f], after[k][f]) for f in KEYS if before[k][f] != after[k][f]][:3])
