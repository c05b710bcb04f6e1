"""The ship rule's figures over several gates pooled, per planner (results/baselines/follow_s16).

    python pool.py BEFORE1.jsonl AFTER1.jsonl [BEFORE2.jsonl AFTER2.jsonl ...]

Per planner (bug2, tangent_bug): reached before -> after (pairs gained, lost, two-sided sign
test), `oscillating` endings (and how many of them in `dynamic`, class C: odometry lost to a
mover, not the follower), episodes with a contact, timeouts, other `stuck`, worker CPU-s.
Rows are matched by (suite file, planner, world, seed): each BEFORE/AFTER pair is one gate.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "follow_s13"))
from signtest import load, sign_test


def pooled(paths: list[str]) -> tuple[dict, dict]:
    before, after = {}, {}
    for i in range(0, len(paths), 2):
        before.update({(i, *k): r for k, r in load(paths[i]).items()})
        after.update({(i, *k): r for k, r in load(paths[i + 1]).items()})
    return before, after


def figures(rows: dict, keys: list) -> dict:
    def n(test) -> int:
        return sum(bool(test(rows[k])) for k in keys)
    osc = lambda r: r["outcome"] == "stuck" and r.get("stuck_reason") == "oscillating"  # noqa: E731
    return {
        "reached": n(lambda r: r["outcome"] == "reached"),
        "oscillating": n(osc),
        "of which dynamic": n(lambda r: osc(r) and r["world"] == "dynamic"),
        "contact episodes": n(lambda r: r["collisions"] > 0),
        "timeouts": n(lambda r: r["outcome"] == "timeout"),
        "other stuck": n(lambda r: r["outcome"] == "stuck" and not osc(r)),
        "worker CPU-s": round(sum(r.get("cpu_s") or 0.0 for r in map(rows.get, keys)), 1),
    }


def main() -> None:
    before, after = pooled(sys.argv[1:])
    for planner in ("bug2", "tangent_bug"):
        keys = [k for k in before if k[1] == planner and k in after]
        fb, fa = figures(before, keys), figures(after, keys)
        won = lambda r: r["outcome"] == "reached"  # noqa: E731
        gain = sum(not won(before[k]) and won(after[k]) for k in keys)
        loss = sum(won(before[k]) and not won(after[k]) for k in keys)
        print(f"{planner} (n = {len(keys)}): " + "; ".join(f"{name} {fb[name]} -> {fa[name]}" for name in fb)
              + f"; reached gained {gain}, lost {loss}, sign-test P = {sign_test(gain, gain + loss):.2f}")
        for label, test in (("oscillating", lambda r: r["outcome"] == "stuck" and r.get("stuck_reason") == "oscillating"),
                            ("contact", lambda r: r["collisions"] > 0)):
            new = sorted(k[2] for k in keys if test(after[k]) and not test(before[k]))
            gone = sorted(k[2] for k in keys if test(before[k]) and not test(after[k]))
            print(f"    {label}: new {new}; gone {gone}")


if __name__ == "__main__":
    main()
