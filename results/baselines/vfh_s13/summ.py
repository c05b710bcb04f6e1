"""Per family and in total: reached, contacts (episodes with one), stuck, timeouts, worker CPU s.
(The stuck kinds, pinned or oscillating, come from ``results/baselines/bugs_s7n/compare.py``.)

python results/baselines/vfh_s13/summ.py ROWS.jsonl [ROWS.jsonl ...]
"""
import json
import sys
from collections import defaultdict

for path in sys.argv[1:]:
    with open(path) as fh:
        rows = [json.loads(line) for line in fh]
    families = defaultdict(list)
    for r in rows:
        families[r["world"].rsplit("_", 1)[0]].append(r)
    families["TOTAL"] = rows
    print(path)
    for family, rs in families.items():
        print(f"  {family:10s} n {len(rs):3d} reached {sum(r['outcome'] == 'reached' for r in rs):3d} "
              f"contacts {sum(r['collisions'] for r in rs):3d} ({sum(r['collisions'] > 0 for r in rs)}) "
              f"stuck {sum(r['outcome'] == 'stuck' for r in rs):3d} "
              f"timeout {sum(r['outcome'] == 'timeout' for r in rs):3d} cpu {sum(r['bench_cpu_s'] for r in rs):6.1f}")
