"""CDFs of per-cycle CPU ms saved by results/speed/dstar_kernel_s14/cycle_cpu.py (record mode).

    python cycle_cdf.py OUT.png TITLE LABEL=FILE.npy ...
"""

from __future__ import annotations

import sys

import numpy as np


def plot(out: str, title: str, runs: list[str]) -> None:
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
    plot(sys.argv[1], sys.argv[2], sys.argv[3:])
