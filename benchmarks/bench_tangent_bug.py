"""TangentBug's and Bug2's planning cost per cycle, before and after the incremental echo memory
and the binned range function (issue 16), side by side in one run.

    python benchmarks/bench_tangent_bug.py [--planners tangent_bug,bug2] [--time-s 120] [--seed 0]
                                           [--record OUT.npz --world W --planner P]

For each planner and world (``worlds/paper/congested.yaml`` and the 40 m x 40 m ``clutter_40m``
of ``bench_planning.py``) plays the same episode twice, alternating: ``before`` with the
former implementations (kept below: :class:`LegacyEchoMemory`, which de-duplicated with
``np.unique`` over every point and carved every point each cycle, and the D x M range
function over all bins), ``after`` with the shipped code. Both give the same commands (the
replay tests check that bit for bit), so they play the same episode. Prints per cycle the CPU
time of ``act()`` (``time.process_time``: a loaded machine does not inflate it), median and p99
in ms, the episode's total CPU s, and the after/before ratios.

``--record`` writes a replay file for ``tests/data/planner_replay/`` (the observations and
commands of one episode) with the implementation this checkout has.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from bench_planning import BIG, CpuTimed, big_world  # noqa: E402

from nav_bench.episode import EpisodeSettings  # noqa: E402
from nav_bench.episode.loop import run_episode  # noqa: E402
from nav_bench.interface import Observation  # noqa: E402
from nav_bench.planners import bug2, follow, tangent_bug  # noqa: E402
from nav_bench.planners.follow import world_echoes  # noqa: E402
from nav_bench.planners.registry import make_planner  # noqa: E402
from nav_bench.specs import PlannerSetSpec, WorldSpec  # noqa: E402
from nav_bench.world.load import load_world  # noqa: E402


class LegacyEchoMemory:
    """The echo memory before issue 16 (main at cd00640), verbatim: the reference of ``before``."""

    def __init__(self, horizon: float, capacity: int = 4000, *, carve: bool = False,
                 spacing: float = 0.0, carve_margin: float = 0.15, carve_cone: float = 0.8) -> None:
        self.horizon, self.capacity = horizon, capacity
        self.carve, self.spacing = carve, spacing
        self.carve_margin, self.carve_cone = carve_margin, carve_cone
        self._xy = np.zeros((0, 2))
        self._t = np.zeros(0)

    def clear(self) -> None:
        self._xy, self._t = np.zeros((0, 2)), np.zeros(0)

    def _carve(self, obs: Observation) -> None:
        if len(self._xy) == 0:
            return
        s = obs.robot.sonar
        x, y, yaw = (float(v) for v in obs.pose[:3])
        c, si = math.cos(yaw), math.sin(yaw)
        origin = np.stack([x + c * s.offsets[:, 0] - si * s.offsets[:, 1],
                           y + si * s.offsets[:, 0] + c * s.offsets[:, 1]], axis=1)
        r = np.where(np.isfinite(obs.ranges), np.asarray(obs.ranges, dtype=float), s.max_range)
        d = self._xy[:, None, :] - origin[None, :, :]
        dist = np.hypot(d[..., 0], d[..., 1])
        off = np.abs(np.remainder(np.arctan2(d[..., 1], d[..., 0]) - (yaw + s.angles)[None, :] + math.pi,
                                  2 * math.pi) - math.pi)
        seen_through = (off <= self.carve_cone * s.cone / 2) & (dist < r[None, :] - self.carve_margin)
        keep = ~seen_through.any(axis=1)
        self._xy, self._t = self._xy[keep], self._t[keep]

    def add(self, obs: Observation) -> None:
        if self.carve:
            self._carve(obs)
        pts = world_echoes(obs)
        xy = np.concatenate([self._xy, pts])
        t = np.concatenate([self._t, np.full(len(pts), obs.t)])
        keep = t >= obs.t - self.horizon
        xy, t = xy[keep], t[keep]
        if self.spacing > 0 and len(xy):
            key = np.floor(xy / self.spacing).astype(np.int64)
            _, first = np.unique(key[::-1], axis=0, return_index=True)
            idx = np.sort(len(xy) - 1 - first)
            xy, t = xy[idx], t[idx]
        self._xy, self._t = xy[-self.capacity:], t[-self.capacity:]

    def points(self, center: np.ndarray | None = None, radius: float = math.inf) -> np.ndarray:
        if center is None or not math.isfinite(radius):
            return self._xy.copy()
        d = np.hypot(self._xy[:, 0] - center[0], self._xy[:, 1] - center[1])
        return self._xy[d <= radius]

    def __len__(self) -> int:
        return len(self._xy)


def legacy_binned(points: np.ndarray, xy: np.ndarray, grow: float, bins: np.ndarray) -> np.ndarray:
    """The former range function over all bins (D x M)."""
    return tangent_bug.range_function(points, xy, grow, bins)


@contextlib.contextmanager
def legacy() -> Iterator[None]:
    """The planners with the former echo memory and range function, restored on exit."""
    saved = (follow.EchoMemory, tangent_bug.EchoMemory, bug2.EchoMemory, tangent_bug.binned_range_function)
    follow.EchoMemory = tangent_bug.EchoMemory = bug2.EchoMemory = LegacyEchoMemory  # type: ignore[misc]
    tangent_bug.binned_range_function = legacy_binned
    try:
        yield
    finally:
        (follow.EchoMemory, tangent_bug.EchoMemory, bug2.EchoMemory,
         tangent_bug.binned_range_function) = saved


def episode_cpu(world: WorldSpec, planner: str, time_s: float, seed: int
                ) -> tuple[np.ndarray, float, np.ndarray, str]:
    """Per-cycle CPU ms of ``act()``, the episode's CPU s, the commands (N, 2) and the outcome."""
    spec = PlannerSetSpec(planner=planner)
    agent = make_planner(spec)
    timer = CpuTimed(agent)
    t0 = time.process_time()
    result = run_episode(world, spec, seed=seed, settings=EpisodeSettings(time_s=time_s), planner_instance=agent)
    total = time.process_time() - t0
    return 1e3 * np.asarray(timer.cpu_s), total, np.asarray(result.trace.cmd), str(result.row.outcome)


def record(out: Path, world: WorldSpec, planner: str, time_s: float, seed: int) -> None:
    """Write the observations and commands of one episode to ``out`` (.npz) for the replay tests."""
    spec = PlannerSetSpec(planner=planner)
    agent = make_planner(spec)
    rec: dict[str, list] = {k: [] for k in ("t", "pose", "goal", "ranges", "cmd")}
    seen: list[Observation] = []
    act = agent.act

    def recording_act(obs: Observation):
        cmd = act(obs)
        for key, value in (("t", obs.t), ("pose", obs.pose), ("goal", obs.goal), ("ranges", obs.ranges),
                           ("cmd", [cmd.v, cmd.omega])):
            rec[key].append(np.array(value, dtype=float))
        seen[:] = [obs]
        return cmd

    agent.act = recording_act  # type: ignore[method-assign]
    result = run_episode(world, spec, seed=seed, settings=EpisodeSettings(time_s=time_s), planner_instance=agent)
    robot = seen[0].robot
    np.savez_compressed(out, **{k: np.asarray(v) for k, v in rec.items()}, bounds=np.asarray(seen[0].bounds),
                        dt=seen[0].dt, planner=planner, world=world.name, seconds=time_s,
                        robot_radius=robot.radius, wheel_base=robot.wheel_base, v_max=robot.v_max,
                        omega_max=robot.omega_max, sonar_angles=robot.sonar.angles,
                        sonar_offsets=robot.sonar.offsets, sonar_cone=robot.sonar.cone,
                        sonar_min_range=robot.sonar.min_range, sonar_max_range=robot.sonar.max_range)
    print(f"{out}: {planner} on {world.name}, {len(rec['t'])} cycles, {result.row.outcome}")


def pick_world(name: str) -> WorldSpec:
    return big_world() if name == BIG else load_world(ROOT / "worlds" / "paper" / f"{name}.yaml")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--planners", default="tangent_bug,bug2")
    ap.add_argument("--worlds", default=f"congested,{BIG}")
    ap.add_argument("--time-s", type=float, default=120.0, help="simulated s per episode (120)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--record", type=Path, help="write a replay .npz of --planner on --world and stop")
    ap.add_argument("--world", default="congested")
    ap.add_argument("--planner", default="tangent_bug")
    args = ap.parse_args()
    if args.record:
        record(args.record, pick_world(args.world), args.planner, args.time_s, args.seed)
        return
    print(f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}; {args.time_s:g} simulated s "
          f"at most, seed {args.seed}; CPU ms of act() per cycle")
    print(f"{'planner':12s} {'world':12s} {'outcome':8s} {'cycles':>6s}  {'median':>15s}  {'p99':>15s}"
          f"  {'episode CPU s':>15s}  {'ratio after/before (median, p99, episode)':s}")
    print(f"{'':42s} {'before':>7s} {'after':>7s}  {'before':>7s} {'after':>7s}  {'before':>7s} {'after':>7s}")
    for planner in args.planners.split(","):
        for wname in args.worlds.split(","):
            world = pick_world(wname)
            with legacy():
                ms_b, cpu_b, cmd_b, outcome = episode_cpu(world, planner, args.time_s, args.seed)
            ms_a, cpu_a, cmd_a, _ = episode_cpu(world, planner, args.time_s, args.seed)
            same = cmd_a.shape == cmd_b.shape and bool(np.array_equal(cmd_a, cmd_b))
            med = (float(np.median(ms_b)), float(np.median(ms_a)))
            p99 = (float(np.percentile(ms_b, 99)), float(np.percentile(ms_a, 99)))
            print(f"{planner:12s} {wname:12s} {outcome:8s} {len(ms_a):6d}  {med[0]:7.3f} {med[1]:7.3f}  "
                  f"{p99[0]:7.3f} {p99[1]:7.3f}  {cpu_b:7.2f} {cpu_a:7.2f}  "
                  f"{med[1] / med[0]:5.2f} {p99[1] / p99[0]:5.2f} {cpu_a / cpu_b:5.2f}"
                  f"{'' if same else '  COMMANDS DIFFER'}", flush=True)
    print(f"load average {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
