"""Statistics over stored result rows (all reproducible: bootstrap resampling uses a
fixed-seed generator):

* success rate with a 95% Wilson score interval (good coverage for small n and rates near
  0 or 1, unlike the normal approximation);
* SPL (success weighted by path length) averaged over all episodes, failures counting 0,
  with a 95% percentile-bootstrap interval of the mean;
* time to goal, path length and the motion metrics (acceleration, jerk, curvature, time near
  obstacles, planner ms per cycle) averaged over the episodes that reached the goal;
* ``barn_score`` (protocol barn) averaged over all episodes, failures counting 0;
* map quality (planners that build a grid, :mod:`nav_bench.mapping.quality`): precision,
  recall and phantom-wall share averaged over every episode that has them (reached or not),
  and the number of episodes whose map put a wall across the optimal path;
* paired comparisons of two parameter sets on the same (world, seed, robot): mean difference
  of SPL (all pairs) and of path length (pairs where both reached the goal) with bootstrap
  intervals, and wins / ties / losses by SPL.

With several folders, each parameter set is labelled ``<run>/<label>`` (run = folder name).
"""

from __future__ import annotations

import itertools
import math
from collections import Counter, defaultdict
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from nav_bench.episode.motion import MOTION_FIELDS
from nav_bench.episode.row import OUTCOMES
from nav_bench.reporting.runs import Run, world_of

Z95 = 1.959963984540054  # two-sided 95% quantile of the standard normal

BOOTSTRAP_SEED = 20240611  # fixed: the same results give the same intervals

BOOTSTRAP_SAMPLES = 10_000

TIE_SPL = 1e-6  # SPL differences below this are ties

# BARN difficulty measures (nav_bench.world.difficulty) -> True when larger means harder
DIFFICULTY_MEASURES = {"tortuosity": True, "dispersion": True, "closest_obstacle_m": False,
                       "characteristic_dimension_m": False, "average_visibility_m": False}

MIN_WORLDS_FOR_DIFFICULTY = 6  # thirds of fewer worlds say nothing

MAX_WORLDS_FOR_DIFFICULTY = 300  # computing the measures costs ~0.2 s per world

def wilson_interval(successes: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion; (0, 1) when ``n`` is 0."""
    if n == 0:
        return (0.0, 1.0)
    p = successes / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    return (max(0.0, centre - half), min(1.0, centre + half))

def bootstrap_mean_interval(values: Sequence[float], *, level: float = 0.95,
                            samples: int = BOOTSTRAP_SAMPLES,
                            seed: int = BOOTSTRAP_SEED) -> tuple[float, float]:
    """Percentile-bootstrap interval of the mean of ``values`` (NaN, NaN when empty).

    A fresh ``numpy.random.Generator(seed)`` per call: an interval does not depend on what
    else the report computed before it.
    """
    x = np.asarray(values, dtype=float)
    if x.size == 0:
        return (math.nan, math.nan)
    if x.size == 1 or np.all(x == x[0]):
        return (float(x[0]), float(x[0]))
    rng = np.random.default_rng(seed)
    means = np.empty(samples)
    chunk = max(1, 2_000_000 // x.size)  # bound memory to ~16 MB of indices per chunk
    for start in range(0, samples, chunk):
        stop = min(samples, start + chunk)
        idx = rng.integers(0, x.size, size=(stop - start, x.size))
        means[start:stop] = x[idx].mean(axis=1)
    tail = (1.0 - level) / 2
    lo, hi = np.quantile(means, [tail, 1.0 - tail])
    return (float(lo), float(hi))

def share_reached_within(rows: Sequence[dict[str, Any]], budgets: np.ndarray) -> np.ndarray:
    """For each time budget T (s), the share of ``rows`` that reached the goal within T."""
    reached = np.sort([r["time_s"] for r in rows if r.get("success")])
    return np.searchsorted(reached, np.asarray(budgets, dtype=float), side="right") / max(1, len(rows))

def _mean(values: Iterable[float | None]) -> float:
    x = [v for v in values if v is not None]
    return float(np.mean(x)) if x else math.nan

@dataclass
class GroupStats:
    """Numbers for one group of episodes (a parameter set on a world, or overall)."""

    set: str
    world: str
    planner: str
    n: int
    outcomes: dict[str, int]
    success: float
    success_ci: tuple[float, float]
    spl: float
    spl_ci: tuple[float, float]
    time_s: float  # mean over episodes that reached the goal
    path_m: float  # mean over episodes that reached the goal
    replans: float
    collisions: float
    min_clearance_m: float  # mean of the per-episode minimum
    spl_values: list[float] = field(default_factory=list, repr=False)
    # mean of each motion metric (MOTION_FIELDS) over the episodes that reached the goal and
    # have it (the same episodes as time and path; NaN: none)
    motion: dict[str, float] = field(default_factory=dict)
    barn_score: float = math.nan  # mean over the episodes that have one (failures count 0)
    # map quality over the episodes whose planner kept a grid (all outcomes; NaN: none)
    map_episodes: int = 0  # episodes with map-quality fields
    map_precision: float = math.nan  # mean of map_precision
    map_recall: float = math.nan  # mean of map_recall
    map_phantom_share: float = math.nan  # mean of map_phantom_share
    map_phantom_episodes: int = 0  # episodes with at least one phantom cell on the optimal path

def group_stats(rows: Sequence[dict[str, Any]], set_name: str, world: str) -> GroupStats:
    """Statistics of ``rows`` (all of one parameter set; one world or ``world='all'``)."""
    n = len(rows)
    reached = [r for r in rows if r.get("success")]
    outcomes = Counter(r.get("outcome", "error") for r in rows)
    spl = [float(r.get("spl") or 0.0) for r in rows]
    planners = sorted({str(r.get("planner")) for r in rows})
    return GroupStats(
        set=set_name, world=world, planner=",".join(planners), n=n,
        outcomes={k: outcomes.get(k, 0) for k in OUTCOMES},
        success=len(reached) / n if n else math.nan,
        success_ci=wilson_interval(len(reached), n),
        spl=_mean(spl), spl_ci=bootstrap_mean_interval(spl),
        time_s=_mean(r.get("time_s") for r in reached),
        path_m=_mean(r.get("path_length_m") for r in reached),
        replans=_mean(r.get("replans") for r in rows),
        collisions=_mean(r.get("collisions") for r in rows),
        min_clearance_m=_mean(r.get("min_clearance_m") for r in rows),
        spl_values=spl,
        motion={k: _mean(r.get(k) for r in reached) for k in MOTION_FIELDS},
        barn_score=_mean(r.get("barn_score") for r in rows),
        map_episodes=sum(1 for r in rows if r.get("map_observed_cells") is not None),
        map_precision=_mean(r.get("map_precision") for r in rows),
        map_recall=_mean(r.get("map_recall") for r in rows),
        map_phantom_share=_mean(r.get("map_phantom_share") for r in rows),
        map_phantom_episodes=sum(1 for r in rows if (r.get("map_phantom_cells") or 0) > 0))

def _by(rows: Iterable[dict[str, Any]], key: Callable[[dict[str, Any]], Any]) -> dict[Any, list]:
    out: dict[Any, list] = defaultdict(list)
    for r in rows:
        out[key(r)].append(r)
    return dict(out)

def world_table(rows: Sequence[dict[str, Any]], sets: Sequence[str]) -> dict[str, list[GroupStats]]:
    """world -> stats of every parameter set on it (in ``sets`` order), worlds in first-seen order."""
    worlds = list(dict.fromkeys(r["world"] for r in rows))
    by = _by(rows, lambda r: (r["world"], r["set"]))
    return {w: [group_stats(by[(w, s)], s, w) for s in sets if (w, s) in by] for w in worlds}

def ranking(rows: Sequence[dict[str, Any]], sets: Sequence[str]) -> list[GroupStats]:
    """Parameter sets over all worlds: success rate first, then mean SPL (both descending)."""
    by = _by(rows, lambda r: r["set"])
    stats = [group_stats(by[s], s, "all") for s in sets]
    return sorted(stats, key=lambda g: (-_nan_low(g.success), -_nan_low(g.spl), g.set))

def _nan_low(x: float) -> float:
    return -math.inf if math.isnan(x) else x

@dataclass
class Paired:
    """Set ``a`` against set ``b`` on the episodes both played (same world, seed, robot)."""

    a: str
    b: str
    pairs: int
    d_spl: float
    d_spl_ci: tuple[float, float]
    both_reached: int
    d_path_m: float
    d_path_ci: tuple[float, float]
    wins: int
    ties: int
    losses: int

def paired_comparison(rows_a: Sequence[dict[str, Any]], rows_b: Sequence[dict[str, Any]],
                      a: str, b: str) -> Paired:
    """Differences a - b over episodes matched on (world, seed, robot_id)."""
    def key(r: dict[str, Any]) -> tuple[Any, ...]:
        return (r["world"], r["seed"], r.get("robot_id"))

    ia, ib = {key(r): r for r in rows_a}, {key(r): r for r in rows_b}
    common = [k for k in ia if k in ib]
    d_spl = [float(ia[k].get("spl") or 0.0) - float(ib[k].get("spl") or 0.0) for k in common]
    d_path = [ia[k]["path_length_m"] - ib[k]["path_length_m"] for k in common
              if ia[k].get("success") and ib[k].get("success")]
    wins = sum(d > TIE_SPL for d in d_spl)
    losses = sum(d < -TIE_SPL for d in d_spl)
    return Paired(a=a, b=b, pairs=len(common), d_spl=_mean(d_spl),
                  d_spl_ci=bootstrap_mean_interval(d_spl), both_reached=len(d_path),
                  d_path_m=_mean(d_path), d_path_ci=bootstrap_mean_interval(d_path),
                  wins=wins, ties=len(common) - wins - losses, losses=losses)

def paired_comparisons(rows: Sequence[dict[str, Any]], order: Sequence[str]) -> list[Paired]:
    """Every pair of parameter sets, the better-ranked one first."""
    by = _by(rows, lambda r: r["set"])
    return [paired_comparison(by[a], by[b], a, b) for a, b in itertools.combinations(order, 2)]

def world_difficulties(rows: Sequence[dict[str, Any]], runs: Sequence[Run]
                       ) -> dict[str, dict[str, float]]:
    """world -> its difficulty measures: from the rows (``difficulty``), the world's ``meta``,
    or computed from the stored world (:mod:`nav_bench.world.difficulty`). Worlds without
    them are left out."""
    out: dict[str, dict[str, float]] = {}
    by_world = _by(rows, lambda r: r["world"])
    if len(by_world) > MAX_WORLDS_FOR_DIFFICULTY:
        return out
    for name, mine in by_world.items():
        measures = next((r["difficulty"] for r in mine if isinstance(r.get("difficulty"), dict)),
                        None)
        if measures is None:
            world = world_of(mine, runs)
            if world is None:
                continue
            measures = world.meta.get("difficulty")
            if not isinstance(measures, dict):
                try:
                    from nav_bench.world.difficulty import difficulty
                except ImportError:
                    return {}
                measures = difficulty(world)
        values = {k: float(measures[k]) for k in DIFFICULTY_MEASURES
                  if isinstance(measures.get(k), (int, float))}
        if values:
            out[name] = values
    return out

def difficulty_table(rows: Sequence[dict[str, Any]], order: Sequence[str],
                     measures: dict[str, dict[str, float]]) -> list[list[Any]]:
    """Success rate per parameter set in the easiest, middle and hardest third of the worlds,
    by each difficulty measure. Rows: measure, third, value range, worlds, one cell per set."""
    table: list[list[Any]] = []
    for measure, larger_is_harder in DIFFICULTY_MEASURES.items():
        worlds = sorted((w for w in measures if measure in measures[w]),
                        key=lambda w: measures[w][measure] * (1 if larger_is_harder else -1))
        if len(worlds) < MIN_WORLDS_FOR_DIFFICULTY:
            continue
        for third, group in zip(("easiest", "middle", "hardest"), np.array_split(worlds, 3),
                                strict=True):
            values = [measures[w][measure] for w in group]
            mine = [r for r in rows if r["world"] in set(group)]
            cells = []
            for name in order:
                sel = [r for r in mine if r["set"] == name]
                k = sum(1 for r in sel if r.get("success"))
                cells.append(f"{k / len(sel):.2f} ({len(sel)})" if sel else "–")
            table.append([measure, third, f"{min(values):.2f}–{max(values):.2f}", len(group),
                          *cells])
    return table
