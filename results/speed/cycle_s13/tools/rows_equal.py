# ruff: noqa: E701, E702  (measurement scripts: patch before import, terse)
"""Every row's outcome, time_s, path_length_m, collisions, min_clearance_m equal? + CPU per label."""
import json
import sys
from collections import defaultdict


def load(p):
    return {(r["label"], r["world"], r["seed"]): r for r in map(json.loads, open(p))}
b, a = load(sys.argv[1]), load(sys.argv[2])
keys = ("outcome", "time_s", "path_length_m", "collisions", "min_clearance_m")
diff = [k for k in b if k in a and any(b[k].get(f) != a[k].get(f) for f in keys)]
print(f"pairs {len(set(a) & set(b))} (before {len(b)}, after {len(a)}); rows differing in {keys}: {len(diff)}")
for k in diff: print("  ", k, [(f, b[k].get(f), a[k].get(f)) for f in keys if b[k].get(f) != a[k].get(f)])
cpu = defaultdict(lambda: [0.0, 0.0])
for k in set(a) & set(b):
    cpu[k[0]][0] += b[k]["bench_cpu_s"]; cpu[k[0]][1] += a[k]["bench_cpu_s"]
for lab, (x, y) in sorted(cpu.items()):
    print(f"  {lab:12s} CPU s before {x:7.1f} after {y:7.1f} ratio {y / x:.3f}")
