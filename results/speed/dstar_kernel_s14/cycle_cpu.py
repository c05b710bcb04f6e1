"""Per-cycle CPU ms of a planner's act() on bench_planning's 400 x 400 world, saved for plotting.

    PYTHONPATH=TREE python cycle_cpu.py TREE PLANNER OUT.npy    # PLANNER: name or name:key=value
    python cycle_cpu.py --plot OUT.png LABEL=FILE.npy ...        # CDFs of the saved runs
    python cycle_cpu.py --plot OUT.png --title TITLE LABEL=FILE.npy ...

TREE is the checkout whose benchmarks/bench_planning.py plays the episode (40 simulated s,
seed 0), the same way the benchmark does.
"""

from __future__ import annotations

import sys

import numpy as np


def record(tree: str, planner: str, out: str) -> None:
    sys.path.insert(0, f"{tree}/benchmarks")
    import bench_planning as bp

    _, cpu, outcome = bp.plan_ms(bp.big_world(), planner, 40.0, 0)
    np.save(out, cpu)
    print(f"{planner}: {len(cpu)} cycles, median {np.median(cpu):.3f} ms, p99 "
          f"{np.percentile(cpu, 99):.3f} ms ({outcome})")


def plot(out: str, runs: list[str],
         title: str = "D* Lite on clutter_40m (400 x 400 cells), 40 s, seed 0") -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    for run in runs:
        label, path = run.split("=", 1)
        ms = np.sort(np.load(path))
        ax.plot(ms, np.arange(1, len(ms) + 1) / len(ms), label=f"{label} (median {np.median(ms):.2f})")
    ax.axvline(1.0, color="grey", lw=0.8, ls="--")
    ax.set_xscale("log")
    ax.set_xlabel("CPU ms per control cycle (act), log scale")
    ax.set_ylabel("share of cycles at or below")
    ax.set_title(title)
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if sys.argv[1] == "--plot" and sys.argv[3] == "--title":
        plot(sys.argv[2], sys.argv[5:], sys.argv[4])
    elif sys.argv[1] == "--plot":
        plot(sys.argv[2], sys.argv[3:])
    else:
        record(sys.argv[1], sys.argv[2], sys.argv[3])
