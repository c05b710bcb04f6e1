"""usage: bandinstr.py WORLD.yaml PLANNER TLIMIT

Replay an episode (this tree's code) recording per follower cycle whether the dead-band rule drove;
report, for each contact (true clearance <= 0), the rule in the 1 s before it."""
import math
import sys

import numpy as np

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.planners import follow
from nav_bench.planners.follow import corridor_half_width
from nav_bench.planners.registry import parse_planner_arg
from nav_bench.world.geometry import signed_distances, static_geometry
from nav_bench.world.load import load_world

world_path, pname, tlim = sys.argv[1:4]
band = {}
orig = follow.WallFollower.act
def act(self, obs):
    near = self.nearest(obs)
    target, other = self.distance, math.inf
    if near is not None:
        other = self.other_side_clearance(obs)
        width = near[0] + other
        if 2.0 * corridor_half_width(obs.robot) <= width < 2.0 * self.distance:
            target = 0.5 * width
        else:
            other = math.inf
    ahead = self._ahead(obs, other)
    front = self.front if math.isinf(other) else min(self.front, target + self.ahead_slack)
    cmd = orig(self, obs)
    band[round(obs.t, 1)] = bool(ahead < front and near is not None and ahead > near[0] + self.ahead_slack)
    return cmd
follow.WallFollower.act = act
world = load_world(world_path)
res = run_episode(world, parse_planner_arg(pname), seed=0, settings=EpisodeSettings(time_s=float(tlim)))
tr = res.trace
geo = static_geometry(world)
db, dc = signed_distances(geo, tr.true_pose[:, :2])
clear = np.min(np.concatenate([db, dc], axis=1), axis=1) - 0.18
touch = np.nonzero(clear <= 0.0)[0]
starts = [i for i in touch if i - 1 not in set(touch)]
n_band = sum(band.values())
print(res.row.outcome, res.row.time_s, 'contacts', res.row.collisions, 'band cycles', n_band, 'of', len(band))
for i in starts:
    t = tr.t[i]
    recent = [band.get(round(t - k * 0.1, 1)) for k in range(0, 11)]
    print(f'  touch at {t:.1f} s: band-rule cycles in the last 1 s: {sum(1 for r in recent if r)}; follower active {sum(1 for r in recent if r is not None)}')
