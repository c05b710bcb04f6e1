"""gap_undo_view.py OUT.png: the hand-built 0.55 m gap of tests/planners/test_carving_undo.py
(run with candidate_D.patch applied, which adds that test and the undo modes) after the carving opened it and the robot faced it again for 1 s, with the three undo modes
(10 s memory): every part of the occupied cells near the gap, kept (black) or carved (light
grey), the true boxes (outlined), the robot (circle) and the way-on sectors' H^p."""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from nav_bench.planners.footprint import cell_parts
from tests.planners.test_carving_undo import TOWARD_GAP, open_the_gap_then_face_it

BOXES = [(2.0, 0.5, 2.3, 1.225), (2.0, 1.775, 2.3, 2.5)]


def panel(ax, undo: str) -> None:
    planner, _, faced = open_the_gap_then_face_it(undo, "numpy")
    f, c = planner.frame, planner.carving
    rows, cols = np.nonzero(c.noted)
    centres = np.stack([f.xmin + (cols + 0.5) * f.cell, f.ymin + (rows + 0.5) * f.cell], axis=1)
    parts = cell_parts(centres, f.cell)
    t = 2.5
    kept = c.carved_t[rows, cols] < t - c.memory_s
    near = (np.abs(parts[..., 0] - 2.1) < 0.45) & (np.abs(parts[..., 1] - 1.5) < 0.6)
    ax.scatter(parts[near & ~kept][:, 0], parts[near & ~kept][:, 1], s=4, c="0.85", marker="s")
    ax.scatter(parts[near & kept][:, 0], parts[near & kept][:, 1], s=4, c="k", marker="s")
    for x0, y0, x1, y1 in BOXES:
        ax.add_patch(plt.Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, ec="tab:blue", lw=1.5))
    ax.add_patch(plt.Circle((1.2, 1.5), 0.18, fill=False, ec="tab:green"))
    ax.set_xlim(1.0, 2.55)
    ax.set_ylim(0.9, 2.1)
    ax.set_aspect("equal")
    ax.set_title(f"undo = {undo}\nH^p toward the gap {np.round(faced).astype(int).tolist()}", fontsize=9)


def main(out: str) -> None:
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.2))
    for ax, undo in zip(axes, ["off", "axis", "unexplained"], strict=True):
        panel(ax, undo)
    fig.suptitle(f"0.55 m gap, 10 s memory, after facing it 1 s: kept parts black, carved grey "
                 f"(sectors {TOWARD_GAP}; threshold_low 1500, high 2500)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1])
