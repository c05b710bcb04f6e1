"""Replay an episode recording, each follower cycle: ahead, main's turn test, the sweep test, and
the command. usage: instr13.py WORLD PLANNER TLIMIT"""
import math
import sys

import numpy as np

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.planners.follow import WallFollower
from nav_bench.planners.registry import make_planner, parse_planner_arg
from nav_bench.world.load import load_world

world_path, pname, tlim = sys.argv[1:4]
world = load_world(world_path)
spec = parse_planner_arg(pname)
agent = make_planner(spec)
rec = []
orig_clear = WallFollower._way_clear
orig_act = WallFollower.act
state = {}
def way_clear(self, obs, front):
    r = orig_clear(self, obs, front)
    state['clear'] = r
    return r
def act(self, obs):
    state.clear()
    cmd = orig_act(self, obs)
    near = self.nearest(obs)
    other = self.other_side_clearance(obs)
    ahead = self._ahead(obs, other if near is not None and 0.46 <= near[0] + other < 0.8 else math.inf)
    rec.append((obs.t, obs.pose[0], obs.pose[1], obs.pose[2], near[0] if near else math.inf, other, ahead,
                state.get('clear', -1), cmd.v, cmd.omega, *obs.ranges))
    return cmd
WallFollower._way_clear = way_clear
WallFollower.act = act
res = run_episode(world, spec, seed=0, settings=EpisodeSettings(time_s=float(tlim)), planner_instance=agent)
row = res.row.to_json()
print(row['outcome'], row.get('stuck_reason'), row['time_s'])
R = np.array(rec)
np.save('/tmp/s13fol/rec.npy', R)
T = R[-1, 0]
m = R[:, 0] > T - 30
r = R[m]
print('last 30s cycles', len(r), 'sweep consulted', np.mean(r[:, 7] >= 0), 'clear', np.mean(r[:, 7] == 1), 'blocked', np.mean(r[:, 7] == 0))
for row in r[-60:]:
    print(' '.join(f'{x:6.2f}' for x in row))
