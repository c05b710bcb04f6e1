# ruff: noqa: SIM115, B007, UP031  (measurement scripts: patch before import, terse)
"""Replay captured carving calls with this tree's code; dump outputs and time."""
import pickle
import sys
import time

import numpy as np

from nav_bench.planners.carving import SeeThroughCarving

res = []
ts = []
for f in sys.argv[2:]:
    calls = pickle.load(open(f, "rb"))
    for rep in range(3):
        c = SeeThroughCarving(*calls["init"][0])
        outs = []
        t0 = time.process_time()
        for obs, rows, cols, box, occ in calls["upd"]:
            r = c.update(obs, rows, cols, box, occ)
            outs.append((r.centres, r.parts, r.kept))
        ts.append((time.process_time() - t0) / len(calls["upd"]) * 1e6)
    res.append((outs, c.carved_t, c.seen_t, c.seen_view, c.noted, c.view))
print("us/update min %.1f med %.1f" % (min(ts), np.median(ts)))
pickle.dump(res, open(sys.argv[1], "wb"))
