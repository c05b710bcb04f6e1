"""oracle_families.py SEEDS WORLD.yaml...: VFH+ (this tree's defaults) reading the real-size TRUE
map in place of the sonar grid, one episode per world and seed, one JSON line each (world, seed,
outcome, time_s, collisions, stuck_reason). Diagnostic only.

The true map is ``../vfh_s12/oracle.py``'s (a 0.1 m raster of the world's obstacles, occupied
cells 100, the rest 50, which VFH+ reads as certainty 0), with the obstacles widened by 0.05 m so
the raster's surfaces lie where the real ones do (``../vfh_s18/sonar_vs_true_map.md``, section 5).
SEEDS: ``0-2``. Worlds are read one after the other in one process. With the environment
variable ``ORACLE_PLOT=DIR`` each episode's picture goes to ``DIR/WORLD_sSEED_truemap.png``.
PYTHONPATH=$PWD python results/baselines/vfh_s20/oracle_families.py 0-2 results/baselines/bugs_s6/worlds/*.yaml
"""
import json
import os
import sys
from pathlib import Path

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.planners.registry import parse_planner_arg
from nav_bench.reporting.episode_plot import plot_episode
from nav_bench.specs import load_robot
from nav_bench.world.load import load_world

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "vfh_s12"))
from oracle import OracleVFH  # the true map's one home

INFLATE_M = 0.05


def main(seeds: str, files: list) -> None:
    first, last = map(int, seeds.split("-"))
    spec, robot = parse_planner_arg("vfh_plus"), load_robot()
    for path in files:
        world = load_world(path)
        for seed in range(first, last + 1):
            result = run_episode(world, spec, seed=seed, robot=robot, settings=EpisodeSettings(),
                                 planner_instance=OracleVFH(world, inflate=INFLATE_M))
            row = result.row
            if os.environ.get("ORACLE_PLOT"):
                plot_episode(result.trace, os.path.join(os.environ["ORACLE_PLOT"], f"{row.world}_s{seed}_truemap.png"))
            reason = getattr(row.stuck_reason, "value", row.stuck_reason)
            print(json.dumps({"world": row.world, "seed": seed, "outcome": row.outcome, "time_s": row.time_s,
                              "collisions": row.collisions, "stuck_reason": reason}), flush=True)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
