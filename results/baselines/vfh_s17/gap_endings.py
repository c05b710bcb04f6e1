"""gap_endings.py BEFORE AFTER [SEEDS]: reached on vfh_s16's 30 gap endings (office 2, 4, 11, 12, 16, 17
and clutter 0, 3, 10, 15, seeds 0-2), gained and lost, and the sign test. SEEDS (e.g. ``6-11``)
counts the same ten layouts on other noise seeds."""
import json
import sys
from math import comb

GAPS = {f"office_{i}" for i in (2, 4, 11, 12, 16, 17)} | {f"clutter_{i}" for i in (0, 3, 10, 15)}
FIRST, LAST = map(int, (sys.argv[3] if len(sys.argv) > 3 else "0-2").split("-"))


def reached(path: str) -> dict:
    with open(path) as fh:
        return {(r["world"], r["seed"]): r["outcome"] == "reached" for r in map(json.loads, fh)
                if r["world"] in GAPS and FIRST <= r["seed"] <= LAST}


before, after = reached(sys.argv[1]), reached(sys.argv[2])
keys = sorted(set(before) & set(after))
gained = [f"{w} s{s}" for w, s in keys if after[w, s] and not before[w, s]]
lost = [f"{w} s{s}" for w, s in keys if before[w, s] and not after[w, s]]
n, k = len(gained) + len(lost), min(len(gained), len(lost))
p = 1.0 if n == 0 else min(1.0, 2 * sum(comb(n, i) for i in range(k + 1)) / 2 ** n)
print(f"{len(keys)} gap episodes (seeds {FIRST}-{LAST}): reached {sum(before[k] for k in keys)} -> {sum(after[k] for k in keys)}")
print(f"gained {len(gained)}: {', '.join(gained)}")
print(f"lost {len(lost)}: {', '.join(lost)}")
print(f"sign test P = {p:.3f}")
