"""turnbacks.py LOG...: the cycles where the chosen direction jumps by more than 90 deg from
the previous cycle's (a turn-back) within 0.45 m of the channel entry (5.1, 5.7): where, the heading and the valleys before."""

import itertools
import json
import sys
from pathlib import Path

import numpy as np

for path in sys.argv[1:]:
    rows = [json.loads(line) for line in Path(path).read_text().splitlines()]
    n = 0
    out = []
    for a, b in itertools.pairwise(rows):
        if a["k"] is None or b["k"] is None:
            continue
        d = abs(((b["k"] - a["k"]) * 5 + 180) % 360 - 180)
        if d > 90 and np.hypot(b["xy"][0] - 5.1, b["xy"][1] - 5.7) < 0.45:
            n += 1
            out.append(
                f"t {b['t']:.1f} ({b['xy'][0]:.2f},{b['xy'][1]:.2f}) chose {(a['k'] * 5 + 180) % 360 - 180:.0f} -> {(b['k'] * 5 + 180) % 360 - 180:.0f}"
            )
    print(path, n, "turn-backs near the entry;", "; ".join(out[:6]))
