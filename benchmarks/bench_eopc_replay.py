"""EO/PC's act() per control cycle on real episodes' observations: this tree against a git
revision, side by side, bit for bit.

    python benchmarks/bench_eopc_replay.py [--against main] [--worlds labyrinth,congested,concave_trap]
                                           [--time-s 120] [--seed 0]

Plays one EO/PC episode per paper world (``eopc`` defaults) and records every observation its
planner saw; then replays them through two planners per parameter set (``eopc_paper``,
``eopc_normalized``): this tree's and the one built from ``nav_bench/planners/eopc.py``,
``mapping/occupancy.py`` and ``mapping/visits.py`` as they are at git revision ``--against``.
The two are called alternately, observation by observation, so they share the machine's load;
each call's CPU time (``time.process_time``) is recorded. Replaying is open loop: both planners
see the recorded observations whatever they command, so they must command the same (checked
call by call) and end with the same grids (checked at the end): ``identical`` says so.

Prints per parameter set and world: cycles, median and mean CPU microseconds of each tree's
``act()`` and the ratios this tree / revision.
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib.util
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from types import ModuleType

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from nav_bench.episode import EpisodeSettings  # noqa: E402
from nav_bench.episode.loop import run_episode  # noqa: E402
from nav_bench.interface import Observation  # noqa: E402
from nav_bench.planners.registry import make_planner  # noqa: E402
from nav_bench.specs import PlannerSetSpec  # noqa: E402
from nav_bench.world.load import load_world  # noqa: E402

PARAMETER_SETS = {"eopc_paper": {}, "eopc_normalized": {"normalize": True}}


def module_at(rev: str, path: str, name: str, imports: dict[str, str]) -> ModuleType:
    """The file ``path`` as it is at git revision ``rev``, imported as module ``name``, with its
    ``from A import`` lines for each ``A`` in ``imports`` pointed at ``imports[A]``."""
    try:
        source = subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:{path}"],
                                check=True, capture_output=True, text=True).stdout
    except subprocess.CalledProcessError as err:
        sys.exit(f"error: --against {rev!r}: {err.stderr.strip()}")
    for old, new in imports.items():
        source = source.replace(f"from {old} import", f"from {new} import")
    file = Path(tempfile.mkdtemp()) / f"{name}.py"
    file.write_text(source)
    spec = importlib.util.spec_from_file_location(name, file)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def eopc_at(rev: str) -> type:
    """The EOPC planner class of revision ``rev`` with that revision's PMO and PMT."""
    module_at(rev, "nav_bench/mapping/occupancy.py", "occupancy_against", {})
    module_at(rev, "nav_bench/mapping/visits.py", "visits_against", {})
    return module_at(rev, "nav_bench/planners/eopc.py", "eopc_against",
                     {"nav_bench.mapping.occupancy": "occupancy_against",
                      "nav_bench.mapping.visits": "visits_against"}).EOPC


def recorded_observations(world: str, time_s: float, seed: int) -> list[Observation]:
    """Every observation EO/PC's act() sees in one episode on ``worlds/paper/<world>.yaml``
    (arrays copied: the loop may reuse its buffers)."""
    spec = PlannerSetSpec(planner="eopc")
    agent = make_planner(spec)
    act, seen = agent.act, []

    def recording(obs: Observation):
        seen.append(dataclasses.replace(obs, pose=obs.pose.copy(), goal=obs.goal.copy(),
                                        ranges=obs.ranges.copy()))
        return act(obs)

    agent.act = recording
    run_episode(load_world(ROOT / "worlds" / "paper" / f"{world}.yaml"), spec, seed=seed,
                settings=EpisodeSettings(time_s=time_s), planner_instance=agent)
    return seen


def replay(this: object, other: object, observations: list[Observation]) -> tuple[np.ndarray, np.ndarray, bool]:
    """CPU microseconds of each planner's act() per observation, called alternately, and whether
    both commanded the same every time and ended with the same PMO and PMT."""
    this.reset(observations[0], np.random.default_rng(0))
    other.reset(observations[0], np.random.default_rng(0))
    times = np.empty((2, len(observations)))
    same = True
    for i, obs in enumerate(observations):
        t0 = time.process_time_ns()
        mine = this.act(obs)
        t1 = time.process_time_ns()
        theirs = other.act(obs)
        t2 = time.process_time_ns()
        times[:, i] = (t1 - t0) / 1e3, (t2 - t1) / 1e3
        same &= (mine.v, mine.omega) == (theirs.v, theirs.omega)
    same &= (np.array_equal(this.pmo.log_odds, other.pmo.log_odds)
             and np.array_equal(this.pmo.values(), other.pmo.values())
             and np.array_equal(this.pmt.counts, other.pmt.counts))
    return times[0], times[1], bool(same)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", default="main", metavar="REV")
    parser.add_argument("--worlds", default="labyrinth,congested,concave_trap")
    parser.add_argument("--time-s", type=float, default=120.0, help="simulated s per recorded episode")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    other_eopc = eopc_at(args.against)
    recorded = {w: recorded_observations(w, args.time_s, args.seed) for w in args.worlds.split(",")}
    print(f"EOPC.act CPU per cycle (us), this tree vs {args.against}, replaying recorded observations")
    all_same = True
    for label, params in PARAMETER_SETS.items():
        for world, observations in recorded.items():
            this = make_planner(PlannerSetSpec(planner="eopc", params=params))
            mine, theirs, same = replay(this, other_eopc(**params), observations)
            all_same &= same
            print(f"  {label:16s} {world:13s} {len(observations):5d} cycles: {args.against} median "
                  f"{np.median(theirs):6.1f} mean {theirs.mean():6.1f} | this median {np.median(mine):6.1f} "
                  f"mean {mine.mean():6.1f} | ratio median {np.median(mine) / np.median(theirs):.2f} "
                  f"mean {mine.mean() / theirs.mean():.2f} | identical {same}")
    print("identical commands and grids in every replay" if all_same else "DIFFERENCES: see 'identical'")


if __name__ == "__main__":
    main()
