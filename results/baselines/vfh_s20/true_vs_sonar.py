"""true_vs_sonar.py TRUE.jsonl SONAR.jsonl: VFH+ on the true map (oracle_families.py rows)
against the same episodes on the sonar map (a run's episodes.jsonl), paired by (world, seed): per
family and in all, reached on each map, both failing, only one reaching, episodes with a contact,
the sonar map's timeouts that fail on the true map too, and the sign test over the one-sided pairs.
python results/baselines/vfh_s20/true_vs_sonar.py rows/moc1217_truemap_area05.jsonl rows/moc1217_area05.jsonl"""
import collections
import json
import sys
from math import comb


def rows(path: str) -> dict:
    with open(path) as fh:
        return {(r["world"], r["seed"]): r for r in map(json.loads, fh) if r.get("planner", "vfh_plus") == "vfh_plus"}


true, sonar = rows(sys.argv[1]), rows(sys.argv[2])
counts = collections.defaultdict(collections.Counter)
for key in sorted(set(true) & set(sonar)):
    t, s = true[key]["outcome"] == "reached", sonar[key]["outcome"] == "reached"
    for group in (key[0].rsplit("_", 1)[0], "all"):
        c = counts[group]
        c["pairs"] += 1
        c["sonar"] += s
        c["true"] += t
        c["both fail"] += not t and not s
        c["only true"] += t and not s
        c["only sonar"] += s and not t
        c["sonar contact eps"] += sonar[key]["collisions"] > 0
        c["true contact eps"] += true[key]["collisions"] > 0
        c["sonar timeouts"] += sonar[key]["outcome"] == "timeout"
        c["... failing on the true map too"] += sonar[key]["outcome"] == "timeout" and not t
for group, c in counts.items():
    print(f"{group}: " + ", ".join(f"{k} {v}" for k, v in c.items()))
a, b = counts["all"]["only true"], counts["all"]["only sonar"]
n, k = a + b, min(a, b)
print(f"sign test over the one-sided pairs: P = {1.0 if n == 0 else min(1.0, 2 * sum(comb(n, i) for i in range(k + 1)) / 2 ** n):.3f}")
