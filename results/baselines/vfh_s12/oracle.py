"""Diagnostic only: VFH+ (main's defaults) reading the TRUE map (a 0.1 m raster of the world's
obstacles, a cell occupied when its centre lies inside one) in place of the sonar grid.
If an episode that times out on the sonar grid is reached here, the sonar map's smear closed
the way; if it still fails, the histogram/cost rules (or the method) do.
PYTHONPATH=$PWD python results/baselines/vfh_s12/oracle.py WORLD.yaml [inflate=M] [key=value ...]
(inflate: widen the true obstacles by M m; key=value: planner parameters; the environment
variable ORACLE_TRACE=X.npz saves the trace, ORACLE_SEED=N plays seed N, default 0.) Prints the result row's outcome, time, contacts.
The raster covers the world rectangle only, so outer walls outside it are missing."""
import json
import os
import sys

import numpy as np

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.planners.registry import parse_planner_arg
from nav_bench.planners.vfh_plus import VFHPlus
from nav_bench.specs import load_robot
from nav_bench.world.geometry import static_geometry
from nav_bench.world.load import load_world
from nav_bench.world.raster import rasterize


class OracleVFH(VFHPlus):
    """VFH+ whose grid reads the world's true obstacles, widened ``inflate`` m (the sonar map is
    still built, unread)."""

    def __init__(self, world, inflate: float = 0.0, **kw):
        super().__init__(**kw)
        self._world, self._inflate = world, inflate

    def reset(self, obs, rng):
        super().reset(obs, rng)
        raster = rasterize(static_geometry(self._world), self.settings.cell, inflate=self._inflate,
                           bounds=tuple(obs.bounds))
        true = np.where(raster.occupied, 100.0, 50.0)
        assert true.shape == self.grid.values().shape, (true.shape, self.grid.values().shape)
        self.grid.values = lambda copy=True: true  # shadow the sonar map's values


def main() -> None:
    seed = int(os.environ.get("ORACLE_SEED", "0"))
    world_file = sys.argv[1]
    kw = {k: float(v) for k, v in (a.split("=") for a in sys.argv[2:] if not a.startswith("inflate"))}
    inflate = next((float(a.split("=")[1]) for a in sys.argv[2:] if a.startswith("inflate=")), 0.0)
    world = load_world(world_file)
    spec = parse_planner_arg("vfh_plus")
    planner = OracleVFH(world, inflate=inflate, **kw)
    res = run_episode(world, spec, seed=seed, robot=load_robot(), settings=EpisodeSettings(), planner_instance=planner)
    r = res.row
    if os.environ.get("ORACLE_TRACE"):
        res.trace.save(os.environ["ORACLE_TRACE"])
    print(json.dumps({"world": r.world, "seed": seed, "outcome": r.outcome, "time_s": r.time_s, "collisions": r.collisions,
                      "path": round(r.path_length_m, 2), "goal_d": round(r.goal_distance_m, 2)}))


if __name__ == "__main__":
    main()
