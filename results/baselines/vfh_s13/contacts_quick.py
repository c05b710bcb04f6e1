"""Contact starts of traces (true clearance <= 2 mm), no replay: time, place, side, speed."""
import glob, json, math, sys
import numpy as np
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data
for path in sys.argv[1:]:
    tr = np.load(path, allow_pickle=True)
    meta = json.loads(str(tr["meta"]))
    world = world_from_data(meta["world"])
    geo = static_geometry(world)
    t, true, cmd = tr["t"], tr["true_pose"], tr["cmd"]
    gap = clearance(geo, true[:, :2].astype(float)) - 0.18
    touch = gap <= 0.002
    starts = [i for i in range(1, len(t)) if touch[i] and not touch[i - 1]]
    out = []
    for i in starts:
        yaw = float(true[i, 2]); ang = np.radians(np.arange(0, 360, 5))
        pts = true[i, :2] + 0.19 * np.stack([np.cos(yaw + ang), np.sin(yaw + ang)], axis=1)
        side = (math.degrees(ang[int(np.argmin(clearance(geo, pts)))]) + 180) % 360 - 180
        out.append(f"t={t[i]:.1f} ({true[i,0]:.2f},{true[i,1]:.2f}) side {side:+.0f} v {cmd[i-1,0]:.2f} w {cmd[i-1,1]:+.2f} min gap {gap[i:i+30].min():+.3f}")
    print(meta["row"]["world"], meta["row"]["outcome"], len(starts), *out, sep="\n  ")
