"""Rows of a side-by-side gate that differ in anything but the bench's own timing and CPU
figures: with the recovery's numbers kept as constants (no new Param), main's rows stay equal
wherever the circling detector never fires, so these are the episodes where it did.

    python diffrows.py BEFORE.jsonl AFTER.jsonl
"""
import json
import sys

IGNORED = {"bench_cpu_s", "bench_wall_s", "cpu_s", "wall_s", "plan_ms_mean", "plan_ms_max", "plan_ms_p95"}


def load(path: str) -> dict:
    return {(r["label"], r["world"], r["seed"]): r for r in map(json.loads, open(path))}


def main() -> None:
    before, after = load(sys.argv[1]), load(sys.argv[2])
    same = 0
    for key in sorted(before.keys() & after.keys()):
        b, a = before[key], after[key]
        fields = [f for f in b if f not in IGNORED and b.get(f) != a.get(f)]
        if not fields:
            same += 1
            continue
        print(f"{key[0]:12s} {key[1]:14s} s{key[2]}: {b['outcome']}:{b.get('stuck_reason')} {b['time_s']} s "
              f"{b['collisions']} contacts -> {a['outcome']}:{a.get('stuck_reason')} {a['time_s']} s "
              f"{a['collisions']} contacts")
    print(f"{same} of {len(before.keys() & after.keys())} pairs equal")


if __name__ == "__main__":
    main()
