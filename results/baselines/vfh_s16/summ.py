"""summ.py BEFORE AFTER [BEFORE AFTER ...]: over the matched rows of the pairs of files, the
totals (reached, episodes with a contact, contacts, timeouts, stuck, pinned, worker CPU s) per
side, the outcomes gained and lost, and the two-sided sign test's P over the changed pairs."""
import json
import sys
from math import comb


def load(path: str) -> dict:
    with open(path) as fh:
        return {(r["planner"], r["world"], r["seed"]): r for r in map(json.loads, fh)}


def totals(rows: list) -> str:
    return (f"reached {sum(r['outcome'] == 'reached' for r in rows)}, "
            f"episodes with a contact {sum(r['collisions'] > 0 for r in rows)}, "
            f"contacts {sum(r['collisions'] for r in rows)}, "
            f"timeouts {sum(r['outcome'] == 'timeout' for r in rows)}, "
            f"stuck {sum(r['outcome'] == 'stuck' for r in rows)} "
            f"(pinned {sum(r.get('stuck_reason') == 'pinned' for r in rows)}), "
            f"CPU s {sum(r.get('bench_cpu_s', 0.0) for r in rows):.1f}")


def main(paths: list) -> None:
    before, after = [], []
    for b, a in zip(paths[::2], paths[1::2], strict=True):
        rb, ra = load(b), load(a)
        keys = sorted(set(rb) & set(ra))
        before += [rb[k] for k in keys]
        after += [ra[k] for k in keys]
    print("before:", totals(before))
    print("after: ", totals(after))
    gained = [f"{a['world']} s{a['seed']}" for b, a in zip(before, after, strict=True)
              if a["outcome"] == "reached" != b["outcome"]]
    lost = [f"{b['world']} s{b['seed']}" for b, a in zip(before, after, strict=True)
            if b["outcome"] == "reached" != a["outcome"]]
    n, k = len(gained) + len(lost), min(len(gained), len(lost))
    p = 1.0 if n == 0 else min(1.0, 2 * sum(comb(n, i) for i in range(k + 1)) / 2 ** n)
    print(f"gained {len(gained)}: {', '.join(gained)}")
    print(f"lost {len(lost)}: {', '.join(lost)}")
    print(f"two-sided sign test over {n} changed pairs: P = {p:.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
