"""TangentBug's (and Bug2's) planning cost per cycle, before and after issue 16's speed-ups,
side by side in one run, and the replay files that prove the commands unchanged.

    python benchmarks/bench_tangent_bug.py [--before f4bd289] [--planners tangent_bug,bug2]
                                           [--worlds clutter_40m,very_complex] [--time-s 60]
                                           [--seed 0] [--repeat 2]
    python benchmarks/bench_tangent_bug.py --record DIR [--planners P,P] [--worlds W,W] [--time-s 60]
    python benchmarks/bench_tangent_bug.py --replay FILE.npz [FILE.npz ...] [--before f4bd289]

Worlds are ``worlds/paper/<name>.yaml`` or ``clutter_40m``, the 40 m x 40 m (400 x 400 cells)
world of ``bench_planning.py``.

* Default: for each planner and world, plays the same episode with the code of commit
  ``--before`` (``git archive`` of it into a temporary directory) and with this checkout, each
  in a fresh process, ``--repeat`` times alternately (both sides see the same machine load;
  each cycle counts its fastest play: other processes only ever add time). Prints the CPU time
  (``time.process_time``) of ``act()`` per cycle, median and p99 in ms, the episode's CPU s
  (simulation included) and the after/before ratios, and whether both sides gave the same
  commands (they must: then they also played the same episode).
* ``--record DIR``: plays each planner on each world with this checkout and writes
  ``DIR/<planner>_<world>_<seconds>s.npz``: every cycle's observation (``t``, ``pose``,
  ``goal``, ``ranges``, with the robot and world fields needed to rebuild it) and the
  command ``act()`` returned (``cmd``: v, omega), bit for bit.
* ``--replay``: feeds the recorded observations to a fresh planner with this checkout's code
  (and, with ``--before``, the code of that commit too, in its own process) and checks every
  command against the recorded one with ``==``; prints the CPU ms per cycle of both. A replay
  runs no simulation, so it times the planner alone on identical input.
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
BEFORE = "f4bd289"  # main before issue 16's TangentBug speed-ups


def load_world_named(root: Path, name: str):
    """``clutter_40m`` (``bench_planning.big_world``) or the paper world ``name``."""
    if name == "clutter_40m":
        from bench_planning import big_world
        return big_world()
    from nav_bench.world.load import load_world
    return load_world(root / "worlds" / "paper" / f"{name}.yaml")


def episode(root: Path, planner: str, world_name: str, time_s: float, seed: int,
            record: bool) -> dict:
    """Play one episode with the code imported from ``root`` (already first on ``sys.path``).
    Returns ``ms`` (CPU ms of each ``act()``), ``total`` (episode CPU s), ``cmd`` (N, 2),
    ``outcome`` and, with ``record``, the observations in the replay format."""
    from nav_bench.episode import EpisodeSettings
    from nav_bench.episode.loop import run_episode
    from nav_bench.planners.registry import make_planner
    from nav_bench.specs import PlannerSetSpec

    world = load_world_named(root, world_name)
    spec = PlannerSetSpec(planner=planner)
    agent = make_planner(spec)
    act = agent.act
    ms: list[float] = []
    rec: dict[str, list] = {k: [] for k in ("t", "pose", "goal", "ranges", "cmd")}
    last = []

    def timed_act(obs):
        t0 = time.process_time()
        cmd = act(obs)
        ms.append(1e3 * (time.process_time() - t0))
        rec["cmd"].append([cmd.v, cmd.omega])
        if record:
            for key, value in (("t", obs.t), ("pose", obs.pose), ("goal", obs.goal), ("ranges", obs.ranges)):
                rec[key].append(np.array(value, dtype=float))
            last[:] = [obs]
        return cmd

    agent.act = timed_act  # type: ignore[method-assign]
    t0 = time.process_time()
    result = run_episode(world, spec, seed=seed, settings=EpisodeSettings(time_s=time_s),
                         planner_instance=agent)
    out = {"ms": np.asarray(ms), "total": time.process_time() - t0,
           "cmd": np.asarray(rec["cmd"], dtype=float), "outcome": str(result.row.outcome)}
    if record:
        obs = last[0]
        robot = obs.robot
        out.update({k: np.asarray(v) for k, v in rec.items() if k != "cmd"})
        out.update(bounds=np.asarray(obs.bounds, dtype=float), dt=obs.dt, planner=planner, world=world_name,
                   seconds=time_s, seed=seed, robot_radius=robot.radius, wheel_base=robot.wheel_base,
                   v_max=robot.v_max, omega_max=robot.omega_max, sonar_angles=robot.sonar.angles,
                   sonar_offsets=robot.sonar.offsets, sonar_cone=robot.sonar.cone,
                   sonar_min_range=robot.sonar.min_range, sonar_max_range=robot.sonar.max_range)
    return out


def load_replay(path: Path) -> dict:
    """The arrays of a replay file, read once (an NpzFile inflates on every access)."""
    with np.load(path) as stored:
        return {key: stored[key] for key in stored.files}


def observations(rec: dict) -> list:
    """The recorded observations of a replay file as :class:`Observation` objects."""
    from nav_bench.interface import Observation, RobotInfo, SonarInfo

    sonar = SonarInfo(angles=rec["sonar_angles"], offsets=rec["sonar_offsets"], cone=float(rec["sonar_cone"]),
                      min_range=float(rec["sonar_min_range"]), max_range=float(rec["sonar_max_range"]))
    robot = RobotInfo(radius=float(rec["robot_radius"]), wheel_base=float(rec["wheel_base"]),
                      v_max=float(rec["v_max"]), omega_max=float(rec["omega_max"]), sonar=sonar)
    bounds = tuple(float(b) for b in rec["bounds"])
    return [Observation(t=float(rec["t"][i]), pose=rec["pose"][i].copy(), goal=rec["goal"][i].copy(),
                        ranges=rec["ranges"][i].copy(), robot=robot, bounds=bounds, dt=float(rec["dt"]))
            for i in range(len(rec["t"]))]


def replay(path: Path) -> dict:
    """Feed a replay file's observations to a fresh planner of its kind (this process's code);
    ``cmd`` (N, 2) it returns and ``ms`` the CPU ms of each ``act()``."""
    from nav_bench.planners.registry import make_planner
    from nav_bench.specs import PlannerSetSpec

    rec = load_replay(path)
    planner = make_planner(PlannerSetSpec(planner=str(rec["planner"])))
    cmds, ms = [], []
    for i, obs in enumerate(observations(rec)):
        if i == 0:
            planner.reset(obs, np.random.default_rng(0))
        t0 = time.process_time()
        cmd = planner.act(obs)
        ms.append(1e3 * (time.process_time() - t0))
        cmds.append([cmd.v, cmd.omega])
    return {"cmd": np.asarray(cmds, dtype=float), "ms": np.asarray(ms), "total": float(np.sum(ms)) / 1e3,
            "outcome": "replay"}


def child(argv: list[str]) -> None:
    """``--child ROOT OUT (play PLANNER WORLD TIME_S SEED | replay FILE)``: run with ROOT's code."""
    root, out, what = Path(argv[0]), argv[1], argv[2]
    sys.path[:0] = [str(root), str(root / "benchmarks")]
    if what == "play":
        planner, world, time_s, seed = argv[3:7]
        res = episode(root, planner, world, float(time_s), int(seed), record=False)
    else:
        res = replay(Path(argv[3]))
    np.savez(out, **res)


def in_process(root: Path, *args: str) -> dict:
    """Run :func:`child` with ``root``'s code in a fresh process; its result."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out.npz"
        env = {**os.environ, "PYTHONPATH": str(root)}
        subprocess.run([sys.executable, __file__, "--child", str(root), str(out), *args], env=env, check=True,
                       stdout=subprocess.DEVNULL)
        return load_replay(out)


def fastest(plays: list[dict]) -> dict:
    """One play from several of the same episode: each cycle's CPU time and the episode's total
    their minimum over the plays."""
    out = dict(plays[0])
    if all(len(p["ms"]) == len(out["ms"]) for p in plays):
        out["ms"] = np.min([p["ms"] for p in plays], axis=0)
    out["total"] = min(float(p["total"]) for p in plays)
    return out


def same_commands(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and bool(np.array_equal(a, b))


def before_tree(commit: str, into: str) -> Path:
    """Extract the tree of ``commit`` into the folder ``into``."""
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", commit], check=True,
                             capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", into], input=archive, check=True)
    return Path(into)


def print_header(args: argparse.Namespace, what: str) -> None:
    print(f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}; before = {args.before}, after = "
          f"this checkout; {what}; CPU ms of act() per cycle")
    print(f"{'planner':12s} {'world':14s} {'outcome':8s} {'cycles':>6s}  {'median':>15s}  {'p99':>15s}"
          f"  {'CPU s':>15s}  after/before: median p99 CPU s")
    print(f"{'':44s}{'before':>7s} {'after':>7s}  {'before':>7s} {'after':>7s}  {'before':>7s} {'after':>7s}")


def print_row(planner: str, world: str, b: dict, a: dict, note: str) -> None:
    med = [float(np.median(x["ms"])) for x in (b, a)]
    p99 = [float(np.percentile(x["ms"], 99)) for x in (b, a)]
    tot = [float(x["total"]) for x in (b, a)]
    print(f"{planner:12s} {world:14s} {a['outcome']!s:8s} {len(a['ms']):6d}  "
          f"{med[0]:7.3f} {med[1]:7.3f}  {p99[0]:7.3f} {p99[1]:7.3f}  {tot[0]:7.2f} {tot[1]:7.2f}  "
          f"{med[1] / med[0]:6.2f} {p99[1] / p99[0]:5.2f} {tot[1] / tot[0]:5.2f}  {note}", flush=True)


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        child(sys.argv[2:])
        return
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", default=BEFORE, help=f"commit of the 'before' code ({BEFORE}: main before "
                    "issue 16's TangentBug speed-ups)")
    ap.add_argument("--planners", default="tangent_bug,bug2")
    ap.add_argument("--worlds", default="clutter_40m,very_complex")
    ap.add_argument("--time-s", type=float, default=60.0, help="simulated s per episode (60)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeat", type=int, default=2, help="plays per side; each cycle counts its fastest (2)")
    ap.add_argument("--record", type=Path, metavar="DIR", help="write replay files into DIR and stop")
    ap.add_argument("--replay", type=Path, nargs="+", metavar="FILE", help="replay these files")
    args = ap.parse_args()
    planners, worlds = args.planners.split(","), args.worlds.split(",")
    if args.record:
        sys.path[:0] = [str(ROOT), str(ROOT / "benchmarks")]
        args.record.mkdir(parents=True, exist_ok=True)
        for planner in planners:
            for world in worlds:
                res = episode(ROOT, planner, world, args.time_s, args.seed, record=True)
                out = args.record / f"{planner}_{world}_{args.time_s:g}s.npz"
                del res["ms"], res["total"]
                np.savez_compressed(out, **res)
                print(f"{out}: {planner} on {world}, {len(res['t'])} cycles, {res['outcome']}, "
                      f"{out.stat().st_size / 1e3:.0f} kB", flush=True)
        return
    failed = False
    with tempfile.TemporaryDirectory() as tmp:
        old = before_tree(args.before, tmp)
        if args.replay:
            print_header(args, f"replays of {len(args.replay)} recorded episodes")
            for path in args.replay:
                rec = load_replay(path)
                runs: dict[str, list[dict]] = {"before": [], "after": []}
                for _ in range(args.repeat):
                    runs["before"].append(in_process(old, "replay", str(path.resolve())))
                    runs["after"].append(in_process(ROOT, "replay", str(path.resolve())))
                b, a = (fastest(runs[side]) for side in ("before", "after"))
                ok_a, ok_b = same_commands(a["cmd"], rec["cmd"]), same_commands(b["cmd"], rec["cmd"])
                failed |= not ok_a
                note = ("commands == recorded" if ok_a and ok_b else
                        f"COMMANDS DIFFER from the recording: after {not ok_a}, before {not ok_b}")
                print_row(str(rec["planner"]), str(rec["world"]), b, a, note)
        else:
            print_header(args, f"{args.time_s:g} simulated s at most, seed {args.seed}")
            for planner in planners:
                for world in worlds:
                    runs = {"before": [], "after": []}
                    for _ in range(args.repeat):  # alternately, so both sides see the same load
                        play = ("play", planner, world, str(args.time_s), str(args.seed))
                        runs["before"].append(in_process(old, *play))
                        runs["after"].append(in_process(ROOT, *play))
                    b, a = (fastest(runs[side]) for side in ("before", "after"))
                    same = same_commands(a["cmd"], b["cmd"])
                    failed |= not same
                    print_row(planner, world, b, a, "same commands" if same else "COMMANDS DIFFER")
    print(f"load average {os.getloadavg()[0]:.1f} at the end")
    if failed:
        sys.exit(1)


if __name__ == "__main__":
    main()
