"""DWA and DWAGlobal per-cycle CPU split into its parts, and this tree's DWA decision against
another tree's on the same inputs (issue 16: median < 1 ms, p99 < 10 ms on the 400 x 400 world).

    python benchmarks/bench_dwa.py [--planners dwa,dwa_global] [--time-s 40] [--seed 0]
        [--before main]

Part 1 plays the episode of ``benchmarks/bench_planning.py --big-only`` (``clutter_40m``, 40 m x
40 m, 400 x 400 cells of 0.1 m) and times per control cycle (process CPU clock, ms):

* ``act``: the whole cycle, as ``bench_planning.py`` times it;
* ``dstar``: ``dwa_global``'s D* Lite part (``update_path``: sonar update of the occupancy grid,
  map changes -> costs, the repair within its budget, the path): the D* Lite planner's code,
  not DWA's;
* ``choose``: DWA's decision (:func:`~nav_bench.planners.dwa.choose_velocity`: window, roll-outs,
  clearances, admissibility, objective);
* ``rest``: the remainder of ``act`` (echo memory, obstacle points, goal, local goal).

Part 2 records every ``choose_velocity`` call's inputs in those episodes and replays them through
this tree's ``choose_velocity`` and the ``--before`` git revision's (default: ``main``;
its ``nav_bench/planners/dwa.py``, loaded with importlib): how many decisions are identical (the same v, omega, score
and admissible count, to the bit) and the median / p99 CPU ms of each.
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from bench_planning import big_world  # noqa: E402

import nav_bench.planners.dwa as dwa_module  # noqa: E402
from nav_bench.episode import EpisodeSettings  # noqa: E402
from nav_bench.episode.loop import run_episode  # noqa: E402
from nav_bench.planners.registry import make_planner  # noqa: E402
from nav_bench.specs import PlannerSetSpec  # noqa: E402


def stats(ms: list[float] | np.ndarray) -> str:
    a = np.asarray(ms, dtype=float)
    if len(a) == 0:
        return f"{'-':>8s} {'-':>8s} {'-':>8s}"
    return f"{np.median(a):8.3f} {np.percentile(a, 99):8.3f} {a.max():8.3f}"


def play(planner: str, time_s: float, seed: int) -> tuple[dict[str, np.ndarray], list[tuple], str]:
    """Per-cycle CPU ms of the parts of ``planner``'s act() over the big world's episode, and the
    recorded choose_velocity calls (args, kwargs)."""
    spec = PlannerSetSpec(planner=planner)
    agent = make_planner(spec)
    parts: dict[str, list[float]] = {"act": [], "dstar": [], "choose": []}
    calls: list[tuple] = []
    cycle = {"dstar": 0.0, "choose": 0.0}
    choose = dwa_module.choose_velocity

    def timed_choose(*args: Any, **kwargs: Any) -> Any:
        t0 = time.process_time()
        out = choose(*args, **kwargs)
        cycle["choose"] += time.process_time() - t0
        calls.append((args, kwargs))
        return out

    act = agent.act
    update_path = getattr(agent, "update_path", None)
    if update_path is not None:
        def timed_update(obs: Any) -> bool:
            t0 = time.process_time()
            out = update_path(obs)
            cycle["dstar"] += time.process_time() - t0
            return out

        agent.update_path = timed_update  # type: ignore[method-assign]

    def timed_act(obs: Any) -> Any:
        cycle["dstar"] = cycle["choose"] = 0.0
        t0 = time.process_time()
        cmd = act(obs)
        parts["act"].append(time.process_time() - t0)
        parts["dstar"].append(cycle["dstar"])
        parts["choose"].append(cycle["choose"])
        return cmd

    agent.act = timed_act  # type: ignore[method-assign]
    dwa_module.choose_velocity = timed_choose
    try:
        result = run_episode(big_world(), spec, seed=seed, settings=EpisodeSettings(time_s=time_s),
                             planner_instance=agent)
    finally:
        dwa_module.choose_velocity = choose
    out = {k: 1e3 * np.asarray(v) for k, v in parts.items()}
    out["rest"] = out["act"] - out["dstar"] - out["choose"]
    return out, calls, str(result.row.outcome)


def load_before(rev: str, tmp: Path) -> Any:
    """``nav_bench/planners/dwa.py`` of git revision ``rev`` as a module (its imports from this
    tree)."""
    source = subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:nav_bench/planners/dwa.py"],
                            check=True, capture_output=True, text=True).stdout
    path = tmp / "dwa_before.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location("dwa_before", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["dwa_before"] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def replay(calls: list[tuple], fn: Any, repeats: int = 3) -> tuple[list[Any], np.ndarray]:
    """The choices of ``fn`` on the recorded calls and its CPU ms per call (best of ``repeats``)."""
    best = np.full(len(calls), math.inf)
    choices: list[Any] = []
    for _ in range(repeats):
        choices = []
        for i, (args, kwargs) in enumerate(calls):
            t0 = time.process_time()
            choices.append(fn(*args, **kwargs))
            best[i] = min(best[i], time.process_time() - t0)
    return choices, 1e3 * best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--planners", default="dwa,dwa_global")
    ap.add_argument("--time-s", type=float, default=40.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--before", default="main", help="git revision to compare with ('' for none)")
    args = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f}; CPU ms per cycle (process clock), "
          f"{args.time_s:g} simulated s on clutter_40m, seed {args.seed}")
    print(f"{'planner':12s} {'part':7s} {'cycles':>6s} {'median':>8s} {'p99':>8s} {'max':>8s}")
    recorded: dict[str, list[tuple]] = {}
    for planner in args.planners.split(","):
        parts, calls, outcome = play(planner, args.time_s, args.seed)
        recorded[planner] = calls
        for part in ("act", "dstar", "choose", "rest"):
            if part == "dstar" and not parts[part].any():
                continue
            print(f"{planner:12s} {part:7s} {len(parts[part]):6d} {stats(parts[part])}")
        print(f"{planner:12s} outcome {outcome}, {len(calls)} DWA decisions")
    if not args.before:
        return
    with tempfile.TemporaryDirectory() as tmp:
        before = load_before(args.before, Path(tmp))
    print(f"\nreplay of the recorded DWA decisions: this tree vs {args.before}")
    for planner, calls in recorded.items():
        if not calls:
            continue
        new, t_new = replay(calls, dwa_module.choose_velocity)
        old, t_old = replay(calls, before.choose_velocity)
        same = sum(tuple(a.__dict__.values()) == tuple(b.__dict__.values()) for a, b in zip(new, old, strict=True))
        print(f"{planner:12s} identical {same}/{len(calls)}; CPU ms per decision: this tree "
              f"median {np.median(t_new):.3f} p99 {np.percentile(t_new, 99):.3f}, before median "
              f"{np.median(t_old):.3f} p99 {np.percentile(t_old, 99):.3f}")
    print(f"load average {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
