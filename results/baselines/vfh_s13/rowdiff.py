"""Rows of two episodes.jsonl files that differ in outcome, time, path length, contacts, min clearance."""
import json
import sys


def load(p):
    return {(r['label'], r['world'], r['seed']): r for r in map(json.loads, open(p))}
b, a = load(sys.argv[1]), load(sys.argv[2])
keys = ('outcome', 'time_s', 'path_length_m', 'collisions', 'min_clearance_m', 'events')
diff = [k for k in b if any(b[k][f] != a[k][f] for f in keys)]
print(f"{len(b)} / {len(a)} rows; {len(diff)} differ in {keys}")
for k in diff:
    print(k, [(f, b[k][f], a[k][f]) for f in keys if b[k][f] != a[k][f]][:3])
