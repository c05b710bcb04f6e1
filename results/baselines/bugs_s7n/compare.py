"""Side-by-side table of two bench_suite row files, matched by (label, world, seed).

    python results/baselines/bugs_s7n/compare.py BEFORE.jsonl AFTER.jsonl [--by family|world]

Only pairs present in both files count (a gate cut short compares what both sides played).
Per planner label and group: reached, episodes with a contact, `stuck` endings by reason,
timeouts, before -> after; then the pairs whose outcome changed.
"""

from __future__ import annotations

import argparse
import json
import re
from collections import Counter, defaultdict
from pathlib import Path


def rows(path: Path) -> dict[tuple[str, str, int], dict]:
    """Rows of a JSONL file keyed by (label, world, seed)."""
    out = {}
    for line in path.read_text().splitlines():
        if line.strip():
            r = json.loads(line)
            out[(r["label"], r["world"], int(r["seed"]))] = r
    return out


def ending(r: dict) -> str:
    """`reached`, `timeout`, `stuck:<reason>`, ... of a row."""
    return f"stuck:{r.get('stuck_reason')}" if r["outcome"] == "stuck" else r["outcome"]


def tally(rs: list[dict]) -> Counter:
    c = Counter(ending(r) for r in rs)
    c["contact"] = sum(1 for r in rs if (r.get("collisions") or 0) > 0)
    c["cpu_s"] = round(sum(r.get("bench_cpu_s", 0.0) for r in rs))
    return c


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("--by", choices=["family", "world", "all"], default="family")
    a = ap.parse_args()
    b, f = rows(a.before), rows(a.after)
    keys = sorted(set(b) & set(f))
    group = {"family": lambda w: re.sub(r"_\d+$", "", w), "world": lambda w: w, "all": lambda w: "all"}[a.by]
    cells: dict[tuple[str, str], list[tuple[dict, dict]]] = defaultdict(list)
    for k in keys:
        cells[(k[0], group(k[1]))].append((b[k], f[k]))
        cells[(k[0], "TOTAL")].append((b[k], f[k]))
    cols = ["reached", "timeout", "stuck:oscillating", "stuck:stopped", "stuck:pinned", "contact", "cpu_s"]
    print(f"{len(keys)} matched pairs")
    print("| planner | group | n | " + " | ".join(cols) + " |")
    print("|---|---|---|" + "---|" * len(cols))
    for (label, g), pairs in sorted(cells.items()):
        tb, ta = tally([p[0] for p in pairs]), tally([p[1] for p in pairs])
        print(f"| {label} | {g} | {len(pairs)} | " + " | ".join(f"{tb[c]} -> {ta[c]}" for c in cols) + " |")
    other = {ending(r) for pair in cells.values() for p in pair for r in p} - set(cols)
    if other:
        print("other endings:", sorted(other))
    print("\nchanged outcomes:")
    for k in keys:
        if ending(b[k]) != ending(f[k]):
            print(f"  {k[0]:12s} {k[1]:16s} s{k[2]}: {ending(b[k])} -> {ending(f[k])}")


if __name__ == "__main__":
    main()
