"""Time to goal against wall length, from a stored long_wall_sweep results folder.

    python examples/plot_long_wall_sweep.py RESULTS_DIR [-o FIGURE.png]

Reads only ``RESULTS_DIR/episodes.jsonl`` (worlds named ``wall_<L>m_<seed>`` by
``configs/suites/long_wall_sweep.yaml``). One panel: each episode a dot (filled: reached, at its
time to goal; hollow: not reached, drawn at the time limit), the median time to goal of the
reached episodes per wall length as a line, one colour per parameter set; the success count
per length is printed as a table on stdout.
"""

from __future__ import annotations

import argparse
import json
import re
from collections import defaultdict
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure


def wall_length(world: str) -> float:
    """Wall length (m) from a world name ``wall_<L>m``."""
    match = re.fullmatch(r"wall_([0-9.]+)m(_[0-9]+)?", world)
    if match is None:
        raise SystemExit(f"unexpected world name {world!r}: expected wall_<L>m[_seed]")
    return float(match.group(1))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path)
    parser.add_argument("-o", "--output", type=Path)
    args = parser.parse_args()
    rows = [json.loads(line) for line in (args.results / "episodes.jsonl").read_text().splitlines() if line]
    by_label: dict[str, dict[float, list[dict]]] = defaultdict(lambda: defaultdict(list))
    for row in rows:
        by_label[row["label"]][wall_length(row["world"])].append(row)
    fig = Figure(figsize=(6.4, 4.2), layout="constrained")
    ax = fig.subplots()
    print("| wall | " + " | ".join(by_label) + " |")
    print("|---|" + "---|" * len(by_label))
    lengths = sorted({wall_length(r["world"]) for r in rows})
    for colour, (label, per_length) in zip(("#1f77b4", "#d62728", "#2ca02c", "#9467bd"), by_label.items(),
                                           strict=False):
        medians = []
        for length in lengths:
            eps = per_length.get(length, [])
            done = [r["time_s"] for r in eps if r["success"]]
            failed = [r["time_limit_s"] for r in eps if not r["success"]]
            ax.scatter([length] * len(done), done, color=colour, s=18, zorder=3)
            ax.scatter([length] * len(failed), failed, facecolors="none", edgecolors=colour, s=30, zorder=3)
            medians.append(float(np.median(done)) if done else np.nan)
        ax.plot(lengths, medians, color=colour, lw=1.5, label=f"{label}: median time to goal")
    for length in lengths:
        cells = []
        for per_length in by_label.values():
            eps = per_length.get(length, [])
            done = [r["time_s"] for r in eps if r["success"]]
            cells.append(f"{len(done)}/{len(eps)}" + (f" · {np.median(done):.0f} s" if done else ""))
        print(f"| {length:g} m | " + " | ".join(cells) + " |")
    ax.set_xlabel("wall length (m)")
    ax.set_ylabel("time to goal (s); hollow: not reached by the limit")
    ax.set_title("EO/PC against a wall across its way", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    out = args.output or args.results / "figures" / "time_vs_wall_length.png"
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
