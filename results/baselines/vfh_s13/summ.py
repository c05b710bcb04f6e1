"""reached, contacts (episodes with one), stuck (pinned), timeouts, CPU s, per side and family."""
import json, sys
from collections import defaultdict
for path in sys.argv[1:]:
    rows = [json.loads(l) for l in open(path)]
    fam = defaultdict(list)
    for r in rows:
        fam[r['world'].rsplit('_', 1)[0]].append(r)
    fam['TOTAL'] = rows
    print(path)
    for f, rs in fam.items():
        print(f"  {f:10s} n {len(rs):3d} reached {sum(r['outcome']=='reached' for r in rs):3d} "
              f"contacts {sum(r['collisions'] for r in rs):3d} ({sum(r['collisions']>0 for r in rs)}) "
              f"stuck {sum(r['outcome']=='stuck' for r in rs):3d} "
              f"(pinned {sum('pinned' in json.dumps(r['events']) and r['outcome']=='stuck' for r in rs)}) "
              f"timeout {sum(r['outcome']=='timeout' for r in rs):3d} cpu {sum(r['bench_cpu_s'] for r in rs):6.1f}")
