"""D* Lite repair after a sonar update vs. A* from scratch, on 100 x 100 and 400 x 400 grids;
and the planner's work per control cycle, this tree's DStarLite against another tree's.

    python benchmarks/bench_dstar.py [--updates 300] [--seed 0] [--cycles 400]
        [--before /work/main/nav_bench/planners/dstar_lite.py] [--episode-s 40] [--parts-only]

Part 3 (``--episode-s`` > 0): the issue-16 episode of ``benchmarks/bench_planning.py``
(``clutter_40m``, 400 x 400 cells, seed ``--seed``) played by both trees' DStarLite, each
cycle's ``act()`` CPU time split into its parts: the sonar map update
(``OccupancyGrid.update``, shared with EO/PC), the map's cost changes (``_map_changes``),
the repair (``PathRepair.cycle``: costs, search, path), the world path (``_refresh_xy``)
and the rest (the follower, its guard, the progress watch and recovery). Printed: median,
p99 and max of the whole cycle, of the cycle without the sonar map update, and of each part.

Part 2 (per control cycle, the issue-16 target: median < 1 ms, p99 < 10 ms on 400 x 400):
both planners' ``update_path`` (map changes -> costs -> repair -> path) is timed every cycle
while a point robot follows its path at 0.5 m/s on a known true world, "sensing" the true
obstacle cells within 2.5 m and +-60 deg of its heading (written straight into the planner's
occupancy grid; the sonar model itself is not timed: it is the same code in both). Scenarios:
``clutter`` (boxes on 8 % of the area) and ``corridor closes`` (a 1 m corridor along the
middle of the map; after 2 m a wall across it shows up ahead and the route must go round the
corridor's outside: the large repair of the issue). "before" is the module given by
``--before`` (default: the main branch's), loaded with importlib; "after" is this tree's.

The setting imitates what :class:`~nav_bench.planners.dstar_lite.DStarLite` does each cycle:

* a cluttered map (random boxes 0.3..1.5 m on 8 % of the area, cell 0.1 m), inflated by
  3 cells (robot radius 0.2 m + margin 0.1 m); start and goal near opposite corners;
  the planner initially knows only the boxes (freespace assumption elsewhere);
* the robot walks its current path 0.5 m (5 cells) between updates; near the goal a new
  episode starts from a random free cell (its initial plan is not timed);
* a *typical sonar update*: a handful (3..8) of cells become occupied on an arc
  1..2.5 m ahead of the robot, within +-30 deg of its heading (an unseen obstacle
  showing up in a front sonar cone); with 30 % chance a few old arc cells are freed again.
  Their inflation changes a few dozen cell costs, which go to ``set_costs``.

Timed per update: D* Lite ``set_costs`` + ``compute`` (the repair) and then the path
extraction; A* from scratch (``astar``) on the same cost grid. Prints median and 99th
percentile (milliseconds) and the ratio A* / D* Lite of the medians.
Target: D* Lite repair under 5 ms median on 100 x 100.
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # this tree's nav_bench, not an installed one

from nav_bench.interface import Observation  # noqa: E402
from nav_bench.mapping.occupancy import OccupancyGrid  # noqa: E402
from nav_bench.planners.dstar_lite import DStarLite, DStarLiteSearch, astar, cell_costs  # noqa: E402
from nav_bench.testing.harness import default_robot  # noqa: E402

INFLATE = 3.0  # cells
INFLATED_COST = 20.0


def cluttered(n: int, rng: np.random.Generator) -> np.ndarray:
    """(n, n) bool occupancy with random boxes covering ~8 % of the grid, corners kept free."""
    occ = np.zeros((n, n), dtype=bool)
    while occ.mean() < 0.08:
        h, w = rng.integers(3, 16, 2)
        r, c = rng.integers(0, n - h), rng.integers(0, n - w)
        occ[r:r + h, c:c + w] = True
    occ[:12, :12] = occ[-12:, -12:] = False
    return occ


def arc_cells(pos: tuple[int, int], heading: float, n: int, rng: np.random.Generator) -> np.ndarray:
    """(k, 2) cells of a short sonar echo arc ahead of ``pos`` (3..8 cells)."""
    dist = rng.uniform(10, 25)
    centre = heading + rng.uniform(-math.radians(30), math.radians(30))
    k = int(rng.integers(3, 9))
    ang = centre + (np.arange(k) - (k - 1) / 2) / dist
    rc = np.stack([pos[0] + dist * np.sin(ang), pos[1] + dist * np.cos(ang)], axis=1)
    rc = np.unique(np.rint(rc).astype(int), axis=0)
    return rc[(rc >= 0).all(axis=1) & (rc < n).all(axis=1)]


def run(n: int, updates: int, seed: int, search_cls: type = DStarLiteSearch) -> dict[str, float]:
    rng = np.random.default_rng(seed)
    occ = cluttered(n, rng)
    start, goal = (5, 5), (n - 6, n - 6)
    cost = cell_costs(occ, INFLATE, INFLATED_COST)
    search = search_cls(cost, start, goal)
    t0 = time.process_time()
    search.compute()
    initial = time.process_time() - t0
    at_once = math.nan  # the first plan by plan_from_scratch (Dijkstra in C), where there is one
    if hasattr(search_cls, "plan_from_scratch"):
        import scipy.sparse.csgraph  # noqa: F401  (imported before timing)

        fresh = search_cls(cost, start, goal)
        t0 = time.process_time()
        fresh.plan_from_scratch()
        at_once = time.process_time() - t0
    repair, extract, scratch, changed, expansions = [], [], [], [], []
    arcs: list[np.ndarray] = []
    pos = start
    for _ in range(updates):
        path = search.path()
        if len(path) < 30:  # near the goal (or cut off): a new episode from a random free cell
            free = np.argwhere(cost == 1.0)
            pos = tuple(int(v) for v in free[rng.integers(len(free))])
            search = search_cls(cost, pos, goal)  # not timed: the episode's initial plan
            search.compute()
            path = search.path()
            if len(path) < 30:
                continue
        pos = path[5]
        ahead = path[min(15, len(path) - 1)] if len(path) > 1 else goal
        heading = math.atan2(ahead[0] - pos[0], ahead[1] - pos[1])
        search.move_start(pos)
        new = arc_cells(pos, heading, n, rng)
        new = new[[tuple(c) not in (pos, goal) for c in new]] if len(new) else new
        occ[new[:, 0], new[:, 1]] = True
        arcs.append(new)
        if len(arcs) > 3 and rng.random() < 0.3:  # an old arc turns out to be a sonar ghost
            old = arcs.pop(0)
            occ[old[:, 0], old[:, 1]] = False
        new_cost = cell_costs(occ, INFLATE, INFLATED_COST)
        new_cost[pos] = min(new_cost[pos], INFLATED_COST)  # the robot's own cell stays passable
        new_cost[goal] = min(new_cost[goal], INFLATED_COST)
        rr, cc = np.nonzero(new_cost != cost)
        cost = new_cost
        changed.append(len(rr))
        before = search.expansions
        t0 = time.process_time()
        search.set_costs(rr, cc, cost[rr, cc])
        search.compute()
        t1 = time.process_time()
        search.path()
        t2 = time.process_time()
        expansions.append(search.expansions - before)
        c_star, _ = astar(cost, pos, goal)
        t3 = time.process_time()
        assert math.isinf(c_star) == math.isinf(search.path_cost)
        assert math.isinf(c_star) or abs(c_star - search.path_cost) < 1e-6, "repair != A*"
        repair.append(t1 - t0)
        extract.append(t2 - t1)
        scratch.append(t3 - t2)
    ms = 1e3
    return {"initial": initial * ms, "at_once": at_once * ms,
            "repair_med": float(np.median(repair)) * ms, "repair_p99": float(np.percentile(repair, 99)) * ms,
            "extract_med": float(np.median(extract)) * ms,
            "astar_med": float(np.median(scratch)) * ms, "astar_p99": float(np.percentile(scratch, 99)) * ms,
            "changed": float(np.median(changed)), "expanded": float(np.median(expansions))}


class SensedGrid(OccupancyGrid):
    """An occupancy grid whose cells the benchmark writes (the sonar update is not timed)."""

    def update(self, pose: np.ndarray, ranges: np.ndarray, sonar: Any) -> None:
        pass

    def values(self, copy: bool = True) -> np.ndarray:
        return self.sensed.copy() if copy else self.sensed


def true_world(kind: str, n: int, rng: np.random.Generator) -> tuple[np.ndarray, tuple, tuple, int]:
    """(occupancy (n, n) bool, start cell, goal cell, cycle at which a wall appears or -1)."""
    if kind == "clutter":
        occ = cluttered(n, rng)
        occ[:10, :10] = occ[-10:, -10:] = False
        return occ, (5, 5), (n - 6, n - 6), -1
    occ = np.zeros((n, n), dtype=bool)
    mid, x0, x1 = n // 2, n // 10, n - n // 10
    occ[mid - 6, x0:x1] = occ[mid + 6, x0:x1] = True  # walls 1.1 m apart: a 1 m corridor
    return occ, (mid, x0 + 2), (mid, x1 - 3), 40  # the block shows up after 2 m (40 cycles)


def load_module(path: str) -> Any:
    """The D* Lite module at ``path`` (another tree's), imported under another name."""
    spec = importlib.util.spec_from_file_location("dstar_before", path)
    module = importlib.util.module_from_spec(spec)
    assert spec.loader is not None
    spec.loader.exec_module(module)
    return module


def cycles(cls: type, kind: str, n: int, count: int, seed: int) -> dict[str, float]:
    """Per-cycle wall time (ms) of ``cls().update_path`` while following its path."""
    rng = np.random.default_rng(seed)
    truth, start, goal, block_at = true_world(kind, n, rng)
    cell, robot = 0.1, default_robot(radius=0.2)
    bounds = (0.0, 0.0, n * cell, n * cell)
    obs_cells = np.argwhere(truth)
    xy = np.array([(start[1] + 0.5) * cell, (start[0] + 0.5) * cell])
    goal_xy = np.array([(goal[1] + 0.5) * cell, (goal[0] + 0.5) * cell])

    def observe(t: float, yaw: float) -> Observation:
        return Observation(t=t, pose=np.array([xy[0], xy[1], yaw]), goal=goal_xy,
                           ranges=np.full(6, 3.0), robot=robot, bounds=bounds, dt=0.1)

    planner = cls()
    planner.reset(observe(0.0, 0.0), np.random.default_rng(seed))
    grid = SensedGrid(bounds, cell=cell)
    grid.sensed = np.full((n, n), 50, dtype=np.uint8)
    planner.grid = grid
    yaw, times, waiting = 0.0, [], 0
    for k in range(count):
        if k == block_at:  # a wall across the corridor, 2 m ahead of the robot
            c = int(xy[0] / cell) + 20
            truth[start[0] - 6:start[0] + 7, c:c + 2] = True
            obs_cells = np.argwhere(truth)
        centre = np.array([xy[1], xy[0]]) / cell
        d = obs_cells - centre
        dist = np.hypot(d[:, 0], d[:, 1])
        ang = np.arctan2(d[:, 0], d[:, 1]) - yaw
        seen = (dist < 25) & (np.cos(ang) > 0.5)
        grid.sensed[obs_cells[seen, 0], obs_cells[seen, 1]] = 100
        t0 = time.process_time()
        planner.update_path(observe(0.1 * k, yaw))
        times.append(time.process_time() - t0)
        repair = getattr(planner, "repair", None)
        waiting += repair is not None and not repair.complete
        path = planner.path_xy
        if len(path) > 1 and k % 2 == 0:  # 0.1 m every other 0.1 s cycle
            ahead = path[min(5, len(path) - 1)]
            yaw = math.atan2(ahead[1] - xy[1], ahead[0] - xy[0])
            xy = path[1].copy()
        if np.hypot(*(xy - goal_xy)) < 0.3:
            break
    ms = np.array(times) * 1e3
    return {"med": float(np.median(ms)), "p99": float(np.percentile(ms, 99)), "max": float(ms.max()),
            "cycles": float(len(ms)), "waiting": float(waiting), "block": float(ms[block_at:block_at + 30].max()) if block_at >= 0 else math.nan}


def compare_cycles(before: str, count: int, seed: int) -> None:
    old = load_module(before).DStarLite
    print(f"\nper control cycle (update_path), ms; before = {before}, after = this tree")
    head = (f"{'scenario':>16} {'grid':>8} {'cycles':>6} | {'before med':>10} {'p99':>7} {'max':>7} | "
            f"{'after med':>9} {'p99':>7} {'max':>7} {'slic':>4} | {'med x':>6} {'p99 x':>6}")
    print(head)
    print("-" * len(head))
    for n in (100, 400):
        for kind in ("clutter", "corridor closes"):
            b = cycles(old, kind, n, count, seed)
            a = cycles(DStarLite, kind, n, count, seed)
            print(f"{kind:>16} {n:>3}x{n:<4} {a['cycles']:6.0f} | {b['med']:10.3f} {b['p99']:7.2f} {b['max']:7.1f} | "
                  f"{a['med']:9.3f} {a['p99']:7.2f} {a['max']:7.1f} {a['waiting']:4.0f} | {b['med'] / a['med']:6.1f} "
                  f"{b['p99'] / a['p99']:6.1f}")
    print("CPU time (process_time) per cycle. slic: cycles that ended with the repair unfinished (the\n"
          "robot kept the free part of its old path or stopped). med x / p99 x: before / after (higher is\n"
          "faster). Target (after, 400 x 400): med < 1, p99 < 10.")


def episode_parts(cls: type, time_s: float, seed: int) -> tuple[dict[str, np.ndarray], str]:
    """Per-cycle CPU ms of the parts of ``cls().act`` in bench_planning's 400 x 400 episode."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from bench_planning import big_world

    from nav_bench.episode import EpisodeSettings
    from nav_bench.episode.loop import run_episode
    from nav_bench.specs import PlannerSetSpec

    planner = cls()
    parts = ("grid", "changes", "repair", "refresh")
    times: dict[str, list[float]] = {k: [] for k in ("act", *parts)}
    now: dict[str, float] = {}

    def timed(name: str, fn: Any) -> Any:
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            t0 = time.process_time()
            try:
                return fn(*args, **kwargs)
            finally:
                now[name] = now.get(name, 0.0) + time.process_time() - t0
        wrapper.timed = True  # type: ignore[attr-defined]
        return wrapper

    act = planner.act

    def timed_act(obs: Observation) -> Any:
        if not getattr(planner.grid.update, "timed", False):
            planner.grid.update = timed("grid", planner.grid.update)
            planner._map_changes = timed("changes", planner._map_changes)
            planner._refresh_xy = timed("refresh", planner._refresh_xy)
        if not getattr(planner.repair.cycle, "timed", False):  # (a restart makes a new one)
            planner.repair.cycle = timed("repair", planner.repair.cycle)
        now.clear()
        t0 = time.process_time()
        cmd = act(obs)
        times["act"].append(time.process_time() - t0)
        for k in parts:
            times[k].append(now.get(k, 0.0))
        return cmd

    planner.act = timed_act  # type: ignore[method-assign]
    spec = PlannerSetSpec(planner="dstar_lite")
    result = run_episode(big_world(), spec, seed=seed, settings=EpisodeSettings(time_s=time_s),
                         planner_instance=planner)
    ms = {k: 1e3 * np.asarray(v) for k, v in times.items()}
    ms["rest"] = ms["act"] - sum(ms[k] for k in parts)
    ms["act - grid"] = ms["act"] - ms["grid"]
    ms["changes+repair+refresh"] = ms["changes"] + ms["repair"] + ms["refresh"]
    return ms, str(result.row.outcome)


def compare_episode(before: str, time_s: float, seed: int) -> None:
    trees = [("after", DStarLite)] if not before else [("before", load_module(before).DStarLite),
                                                        ("after", DStarLite)]
    print(f"\nper control cycle of the 400 x 400 episode (bench_planning's clutter_40m, {time_s:g} s, "
          f"seed {seed}), CPU ms; load average {os.getloadavg()[0]:.2f}")
    rows = ("act", "act - grid", "grid", "changes", "repair", "refresh", "changes+repair+refresh", "rest")
    for label, cls in trees:
        ms, outcome = episode_parts(cls, time_s, seed)
        print(f"{label} ({outcome}, {len(ms['act'])} cycles)")
        for k in rows:
            v = ms[k]
            print(f"  {k:>24}: median {np.median(v):7.3f}  p99 {np.percentile(v, 99):7.3f}  max {v.max():8.2f}")
    print("act: the whole cycle; act - grid: without the sonar map update (another module's cost);\n"
          "changes+repair+refresh: D* Lite's own planning. Target: act median < 1, p99 < 10.")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--updates", type=int, default=300, help="sonar updates per grid size")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--cycles", type=int, default=400, help="control cycles per scenario (part 2)")
    ap.add_argument("--before", default=str(Path("/work/main/nav_bench/planners/dstar_lite.py")),
                    help="D* Lite module to compare with; '' skips the comparison")
    ap.add_argument("--episode-s", type=float, default=40.0,
                    help="simulated s of the part-3 episode (0 skips it)")
    ap.add_argument("--parts-only", action="store_true", help="only part 3")
    args = ap.parse_args()
    if args.parts_only:
        compare_episode(args.before, args.episode_s, args.seed)
        return
    print(f"load average {os.getloadavg()[0]:.2f}; {args.updates} updates per grid; times in ms")
    old = load_module(args.before).DStarLiteSearch if args.before else None
    head = (f"{'grid':>9} {'tree':>6} {'initial':>8} {'at once':>8} {'cells chg':>9} {'expanded':>8} {'D* med':>7} "
            f"{'D* p99':>7} {'path':>6} {'A* med':>7} {'A* p99':>7} {'A*/D*':>6}")
    print(head)
    print("-" * len(head))
    for n in (100, 400):
        for label, cls in (("before", old), ("after", DStarLiteSearch)):
            if cls is None:
                continue
            r = run(n, args.updates, args.seed, cls)
            print(f"{n:>4}x{n:<4} {label:>6} {r['initial']:8.1f} {r['at_once']:8.1f} {r['changed']:9.0f} {r['expanded']:8.0f} "
                  f"{r['repair_med']:7.2f} {r['repair_p99']:7.2f} {r['extract_med']:6.2f} "
                  f"{r['astar_med']:7.2f} {r['astar_p99']:7.2f} {r['astar_med'] / r['repair_med']:6.1f}")
    print("initial: the first plan expanded cell by cell; at once: the same by plan_from_scratch (the\n"
          "whole grid, SciPy's Dijkstra); D* med/p99: set_costs + compute (the repair, unbudgeted, binary\n"
          "inflation); path: extracting the cell path afterwards; A*: planning from scratch on the same\n"
          "costs. CPU time.")
    if args.before:
        compare_cycles(args.before, args.cycles, args.seed)
    if args.episode_s > 0:
        compare_episode(args.before, args.episode_s, args.seed)


if __name__ == "__main__":
    main()
