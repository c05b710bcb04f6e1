"""showlog.py LOG T0 T1: per cycle, pose, goal/heading/chosen direction (deg) and the free valleys of the masked histogram (deg)."""

import json
import sys
from pathlib import Path


def valleys(m):
    n = len(m)
    free = [i for i in range(n) if m[i] == "0"]
    if not free:
        return "none"
    out, start, prev = [], free[0], free[0]
    for i in [*free[1:], None]:
        if i is not None and i == prev + 1:
            prev = i
            continue
        a, b = start * 5, prev * 5
        out.append(f"{(a + 180) % 360 - 180}..{(b + 180) % 360 - 180}")
        if i is not None:
            start = prev = i
    return " ".join(out)


t0, t1 = map(float, sys.argv[2:4])
for line in Path(sys.argv[1]).read_text().splitlines():
    r = json.loads(line)
    if t0 <= r["t"] <= t1:
        k = None if r["k"] is None else (r["k"] * 5 + 180) % 360 - 180
        kh = round(r["kh"]) % 72
        print(
            f"t {r['t']:5.1f} xy {r['xy'][0]:.3f},{r['xy'][1]:.3f} hd {r['yaw'] * 57.2958:6.1f} goal {(r['kt'] * 5 + 180) % 360 - 180:6.1f} chosen {k if k is None else round(k, 1)} x{r['factor']:.0f} H(heading) {r['prim'][kh]} free: {valleys(r['masked'])}"
        )
