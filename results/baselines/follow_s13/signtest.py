"""Sign test over matched pairs: reached gained vs lost, per planner, families + paper.

    python signtest.py FAM_BEFORE FAM_AFTER PAPER_BEFORE PAPER_AFTER

Prints, per planner, reached before -> after, the pairs gained and lost, the two-sided sign
test's P over the changed pairs, episodes with a contact and `oscillating` endings.
"""

import json
import sys
from math import comb


def load(path: str) -> dict:
    with open(path) as fh:
        return {(r["planner"], r["world"], r["seed"]): r for r in map(json.loads, fh)}


def sign_test(k: int, n: int) -> float:
    """Two-sided P of k or fewer (or n - k or more) successes in n fair coin flips."""
    if n == 0:
        return 1.0
    return min(1.0, 2 * sum(comb(n, i) for i in range(min(k, n - k) + 1)) / 2 ** n)


def count(rows: dict, keys: list, test) -> int:
    return sum(bool(test(rows[k])) for k in keys)


def main() -> None:
    before = {**load(sys.argv[1]), **load(sys.argv[3])}
    after = {**load(sys.argv[2]), **load(sys.argv[4])}
    reached = lambda r: r["outcome"] == "reached"  # noqa: E731
    contact = lambda r: r["collisions"] > 0  # noqa: E731
    oscillating = lambda r: r["outcome"] == "stuck" and r.get("stuck_reason") == "oscillating"  # noqa: E731
    for planner in ("bug2", "tangent_bug"):
        keys = [k for k in before if k[0] == planner and k in after]
        gain = sum(not reached(before[k]) and reached(after[k]) for k in keys)
        loss = sum(reached(before[k]) and not reached(after[k]) for k in keys)
        print(f"{planner}: n={len(keys)} reached {count(before, keys, reached)} -> {count(after, keys, reached)}"
              f" (gained {gain}, lost {loss}, two-sided sign-test P = {sign_test(gain, gain + loss):.2f});"
              f" contact episodes {count(before, keys, contact)} -> {count(after, keys, contact)};"
              f" oscillating {count(before, keys, oscillating)} -> {count(after, keys, oscillating)}")


if __name__ == "__main__":
    main()
