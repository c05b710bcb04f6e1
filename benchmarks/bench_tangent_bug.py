"""TangentBug's and Bug2's planning cost per cycle before and after the incremental echo memory
and the binned range function (issue 16), side by side in one run.

    python benchmarks/bench_tangent_bug.py [--before cd00640] [--planners tangent_bug,bug2]
                                           [--worlds congested,clutter_40m] [--time-s 120] [--seed 0]
                                           [--repeat 2]
    python benchmarks/bench_tangent_bug.py --record OUT.npz [--world congested] [--planner tangent_bug]

For each planner and world (``worlds/paper/<name>.yaml``, or the 40 m x 40 m ``clutter_40m`` of
``bench_planning.py``) plays the same episode twice, alternately, each in a fresh process:
``before`` with the code of commit ``--before`` (``git archive`` of it into a temporary
directory), ``after`` with this checkout. Both give the same commands (the replay tests check
that bit for bit; here the commands are compared too), so they play the same episode. Prints
per cycle the CPU time of ``act()`` (``time.process_time``: a loaded machine does not inflate
it much), median and p99 in ms, the episode's total CPU s (simulation included), and the
after/before ratios.

With ``--repeat N`` each side plays N times, alternately, and each cycle counts its fastest
play: on a shared machine other processes only ever add time.

``--record`` writes a replay file for ``tests/data/planner_replay/`` (the observations and
commands of one episode) with the code of this checkout.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def load_world_named(name: str):
    """``clutter_40m`` (from the root's ``benchmarks/bench_planning.py``) or a paper world."""
    if name == "clutter_40m":
        from bench_planning import big_world
        return big_world()
    from nav_bench.world.load import load_world
    return load_world(Path(sys.path[0]) / "worlds" / "paper" / f"{name}.yaml")


def child(root: str, planner: str, world_name: str, time_s: float, seed: int, out: str) -> None:
    """Play one episode with the code under ``root``; write per-cycle CPU ms of ``act()``, the
    episode's CPU s and the commands to ``out`` (.npz)."""
    sys.path[:0] = [root, str(Path(root) / "benchmarks")]
    from nav_bench.episode import EpisodeSettings
    from nav_bench.episode.loop import run_episode
    from nav_bench.planners.registry import make_planner
    from nav_bench.specs import PlannerSetSpec

    world = load_world_named(world_name)
    spec = PlannerSetSpec(planner=planner)
    agent = make_planner(spec)
    cpu_ms: list[float] = []
    act = agent.act

    def timed_act(obs):
        t0 = time.process_time()
        cmd = act(obs)
        cpu_ms.append(1e3 * (time.process_time() - t0))
        return cmd

    agent.act = timed_act  # type: ignore[method-assign]
    t0 = time.process_time()
    result = run_episode(world, spec, seed=seed, settings=EpisodeSettings(time_s=time_s), planner_instance=agent)
    total = time.process_time() - t0
    np.savez(out, ms=np.asarray(cpu_ms), total=total, cmd=np.asarray(result.trace.cmd),
             outcome=str(result.row.outcome))


def play(root: Path, planner: str, world: str, time_s: float, seed: int) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out.npz"
        env = {**os.environ, "PYTHONPATH": str(root)}
        subprocess.run([sys.executable, __file__, "--child", str(root), planner, world, str(time_s), str(seed),
                        str(out)], env=env, check=True, stdout=subprocess.DEVNULL)
        with np.load(out) as f:
            return {k: f[k] for k in f.files}


def fastest(plays: list[dict]) -> dict:
    """One play of the same episode from several: each cycle's CPU time and the episode's total
    as their minimum over the plays (the load of other processes only adds time)."""
    out = dict(plays[0])
    if all(len(p["ms"]) == len(out["ms"]) for p in plays):
        out["ms"] = np.min([p["ms"] for p in plays], axis=0)
    out["total"] = min(float(p["total"]) for p in plays)
    return out


def record(out: Path, planner: str, world_name: str, time_s: float, seed: int) -> None:
    """Write the observations and commands of one episode to ``out`` (.npz) for the replay tests."""
    sys.path[:0] = [str(ROOT), str(ROOT / "benchmarks")]
    from nav_bench.episode import EpisodeSettings
    from nav_bench.episode.loop import run_episode
    from nav_bench.planners.registry import make_planner
    from nav_bench.specs import PlannerSetSpec

    world = load_world_named(world_name)
    spec = PlannerSetSpec(planner=planner)
    agent = make_planner(spec)
    rec: dict[str, list] = {k: [] for k in ("t", "pose", "goal", "ranges", "cmd")}
    last = []
    act = agent.act

    def recording_act(obs):
        cmd = act(obs)
        for key, value in (("t", obs.t), ("pose", obs.pose), ("goal", obs.goal), ("ranges", obs.ranges),
                           ("cmd", [cmd.v, cmd.omega])):
            rec[key].append(np.array(value, dtype=float))
        last[:] = [obs]
        return cmd

    agent.act = recording_act  # type: ignore[method-assign]
    result = run_episode(world, spec, seed=seed, settings=EpisodeSettings(time_s=time_s), planner_instance=agent)
    obs = last[0]
    robot = obs.robot
    np.savez_compressed(out, **{k: np.asarray(v) for k, v in rec.items()}, bounds=np.asarray(obs.bounds),
                        dt=obs.dt, planner=planner, world=world_name, seconds=time_s,
                        robot_radius=robot.radius, wheel_base=robot.wheel_base, v_max=robot.v_max,
                        omega_max=robot.omega_max, sonar_angles=robot.sonar.angles,
                        sonar_offsets=robot.sonar.offsets, sonar_cone=robot.sonar.cone,
                        sonar_min_range=robot.sonar.min_range, sonar_max_range=robot.sonar.max_range)
    print(f"{out}: {planner} on {world_name}, {len(rec['t'])} cycles, {result.row.outcome}")


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        root, planner, world, time_s, seed, out = sys.argv[2:8]
        child(root, planner, world, float(time_s), int(seed), out)
        return
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", default="cd00640", help="commit of the 'before' code (cd00640: main before issue 16)")
    ap.add_argument("--planners", default="tangent_bug,bug2")
    ap.add_argument("--worlds", default="congested,clutter_40m")
    ap.add_argument("--time-s", type=float, default=120.0, help="simulated s per episode (120)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeat", type=int, default=2,
                    help="plays per side; each cycle's time is its minimum over them (2)")
    ap.add_argument("--record", type=Path, help="write a replay .npz of --planner on --world and stop")
    ap.add_argument("--world", default="congested")
    ap.add_argument("--planner", default="tangent_bug")
    args = ap.parse_args()
    if args.record:
        record(args.record, args.planner, args.world, args.time_s, args.seed)
        return
    print(f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}; before = {args.before}, after = "
          f"this checkout; {args.time_s:g} simulated s at most, seed {args.seed}; CPU ms of act() per cycle")
    print(f"{'planner':12s} {'world':12s} {'outcome':8s} {'cycles':>6s}  {'median':>15s}  {'p99':>15s}"
          f"  {'episode CPU s':>15s}  ratio after/before: median p99 episode")
    print(f"{'':42s}{'before':>7s} {'after':>7s}  {'before':>7s} {'after':>7s}  {'before':>7s} {'after':>7s}")
    with tempfile.TemporaryDirectory() as before_root:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", args.before], check=True,
                                 capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", before_root], input=archive, check=True)
        for planner in args.planners.split(","):
            for world in args.worlds.split(","):
                runs: dict[str, list[dict]] = {"before": [], "after": []}
                for _ in range(args.repeat):  # alternately, so both sides see the same load
                    runs["before"].append(play(Path(before_root), planner, world, args.time_s, args.seed))
                    runs["after"].append(play(ROOT, planner, world, args.time_s, args.seed))
                b, a = (fastest(runs[side]) for side in ("before", "after"))
                same = a["cmd"].shape == b["cmd"].shape and bool(np.array_equal(a["cmd"], b["cmd"]))
                med = [float(np.median(x["ms"])) for x in (b, a)]
                p99 = [float(np.percentile(x["ms"], 99)) for x in (b, a)]
                tot = [float(x["total"]) for x in (b, a)]
                print(f"{planner:12s} {world:12s} {a['outcome']!s:8s} {len(a['ms']):6d}  "
                      f"{med[0]:7.3f} {med[1]:7.3f}  {p99[0]:7.3f} {p99[1]:7.3f}  {tot[0]:7.2f} {tot[1]:7.2f}  "
                      f"{med[1] / med[0]:6.2f} {p99[1] / p99[0]:5.2f} {tot[1] / tot[0]:5.2f}"
                      f"{'' if same else '  COMMANDS DIFFER'}", flush=True)
    print(f"load average {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
