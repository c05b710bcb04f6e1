"""``nav-bench report``: tables, comparisons and figures from stored results only.

Reads results folders (``episodes.jsonl``, ``run.json``, ``traces/``) and writes
``report.md``, ``summary.csv`` and ``figures/*.png``. Nothing is simulated again.

Statistics (all reproducible: bootstrap resampling uses a fixed-seed generator):

* success rate with a 95% Wilson score interval (good coverage for small n and rates near
  0 or 1, unlike the normal approximation);
* SPL (success weighted by path length) averaged over all episodes, failures counting 0,
  with a 95% percentile-bootstrap interval of the mean;
* time to goal and path length averaged over the episodes that reached the goal;
* paired comparisons of two parameter sets on the same (world, seed, robot): mean difference
  of SPL (all pairs) and of path length (pairs where both reached the goal) with bootstrap
  intervals, and wins / ties / losses by SPL.

With several folders, each parameter set is labelled ``<run>/<label>`` (run = folder name).
"""

from __future__ import annotations

import csv
import io
import itertools
import math
from collections import Counter, defaultdict
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from nav_bench.errors import InputError
from nav_bench.store import OUTCOMES, ResultsStore

Z95 = 1.959963984540054  # two-sided 95% quantile of the standard normal
BOOTSTRAP_SEED = 20240611  # fixed: the same results give the same intervals
BOOTSTRAP_SAMPLES = 10_000
TIE_SPL = 1e-6  # SPL differences below this are ties
MAX_TRAJECTORY_WORLDS = 24  # trajectory figures beyond this many worlds are left out
# BARN difficulty measures (nav_bench.world.difficulty) -> True when larger means harder
DIFFICULTY_MEASURES = {"tortuosity": True, "dispersion": True, "closest_obstacle_m": False,
                       "characteristic_dimension_m": False, "average_visibility_m": False}
MIN_WORLDS_FOR_DIFFICULTY = 6  # thirds of fewer worlds say nothing
MAX_WORLDS_FOR_DIFFICULTY = 300  # computing the measures costs ~0.2 s per world


# --------------------------------------------------------------------------- statistics
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


# --------------------------------------------------------------------------- loading
@dataclass
class Run:
    """One results folder."""

    name: str
    folder: Path
    meta: dict[str, Any]
    rows: list[dict[str, Any]]


def load_runs(dirs: Sequence[Path]) -> list[Run]:
    """The runs in ``dirs``; each row gets ``run`` (folder name) and ``set`` (its group label)."""
    if not dirs:
        raise InputError("report needs at least one results folder")
    runs: list[Run] = []
    names: Counter[str] = Counter()
    for d in dirs:
        store = ResultsStore(d)
        if not store.episodes_path.exists() and not store.run_path.exists():
            raise InputError(f"{d} is not a nav-bench results folder (no episodes.jsonl or "
                             f"run.json)")
        meta = store.read_run() if store.run_path.exists() else {}
        name = Path(d).resolve().name
        names[name] += 1
        if names[name] > 1:
            name = f"{name}#{names[name]}"
        rows = store.checked_rows()  # a row a report cannot read is named, not guessed at
        for r in rows:
            r["run"] = name
            r.setdefault("label", r.get("planner", "?"))
        runs.append(Run(name, Path(d), meta, rows))
    several = len(runs) > 1
    for run in runs:
        for r in run.rows:
            r["set"] = f"{run.name}/{r['label']}" if several else r["label"]
    return runs


# --------------------------------------------------------------------------- tables
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
        spl_values=spl)


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
    from nav_bench.plots import world_of

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


# --------------------------------------------------------------------------- formatting
def _f(x: float, digits: int = 2) -> str:
    return "–" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.{digits}f}"


def _ci(x: float, ci: tuple[float, float], digits: int = 2) -> str:
    if math.isnan(x):
        return "–"
    if math.isnan(ci[0]):
        return _f(x, digits)
    return f"{x:.{digits}f} [{ci[0]:.{digits}f}, {ci[1]:.{digits}f}]"


def _signed(x: float, ci: tuple[float, float], digits: int = 3) -> str:
    if math.isnan(x):
        return "–"
    return f"{x:+.{digits}f} [{ci[0]:+.{digits}f}, {ci[1]:+.{digits}f}]"


def _md_table(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    def cell(v: Any) -> str:
        return str(v).replace("|", "\\|")

    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(cell(v) for v in r) + " |" for r in rows]
    return "\n".join(lines)


def _outcome_text(o: dict[str, int]) -> str:
    return " / ".join(str(o.get(k, 0)) for k in OUTCOMES)


def summary_csv(ranked: Sequence[GroupStats], per_world: dict[str, list[GroupStats]]) -> str:
    """One line per (parameter set, world) and per parameter set over all worlds."""
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["set", "planner", "world", "episodes", *OUTCOMES, "success_rate", "success_lo",
                "success_hi", "spl_mean", "spl_lo", "spl_hi", "time_to_goal_s", "path_length_m",
                "replans_mean", "collisions_mean", "min_clearance_m"])

    def num(x: float) -> str:
        return "" if math.isnan(x) else f"{x:.6g}"

    for g in [*(g for stats in per_world.values() for g in stats), *ranked]:
        w.writerow([g.set, g.planner, g.world, g.n, *(g.outcomes[k] for k in OUTCOMES),
                    num(g.success), num(g.success_ci[0]), num(g.success_ci[1]), num(g.spl),
                    num(g.spl_ci[0]), num(g.spl_ci[1]), num(g.time_s), num(g.path_m),
                    num(g.replans), num(g.collisions), num(g.min_clearance_m)])
    return out.getvalue()


def _runs_section(runs: Sequence[Run]) -> str:
    rows = []
    for run in runs:
        m = run.meta
        git = m.get("git") or {}
        commit = (git.get("commit") or "")[:10] + (" (modified)" if git.get("dirty") else "")
        executor = m.get("executor") or {}
        rows.append([run.name, (m.get("suite") or {}).get("name", "?"),
                     f"{len(run.rows)} / {m.get('total', '?')}", m.get("status", "?"),
                     m.get("started", "?"), m.get("host", "?"),
                     f"{executor.get('name', '?')} x{executor.get('workers', '?')}",
                     m.get("nav_bench", "?"), commit or "–"])
    return _md_table(["run", "suite", "episodes", "status", "started", "host", "executor",
                      "nav-bench", "commit"], rows)


# --------------------------------------------------------------------------- the report
def _report_dir(dirs: Sequence[Path], out: Path | None) -> Path:
    if out is not None:
        return Path(out)
    if len(dirs) == 1:
        return Path(dirs[0])
    return Path(dirs[0]) / ("compare-" + "-".join(Path(d).resolve().name for d in dirs[1:]))


def write_report(dirs: list[Path], out: Path | None = None) -> Path:
    """Write ``report.md``, ``summary.csv`` and ``figures/`` for ``dirs``; returns report.md.

    ``out`` defaults to the results folder itself (one folder) or
    ``<first>/compare-<others>`` (several folders).
    """
    from nav_bench import plots

    runs = load_runs([Path(d) for d in dirs])
    rows = [r for run in runs for r in run.rows]
    if not rows:
        raise InputError(f"no episodes stored in {', '.join(str(d) for d in dirs)}")
    folder = _report_dir(dirs, out)
    figures = folder / "figures"
    figures.mkdir(parents=True, exist_ok=True)

    sets = list(dict.fromkeys(r["set"] for r in rows))
    ranked = ranking(rows, sets)
    order = [g.set for g in ranked]
    per_world = world_table(rows, order)
    pairs = paired_comparisons(rows, order) if len(order) > 1 else []

    (folder / "summary.csv").write_text(summary_csv(ranked, per_world), encoding="utf-8")

    rel = lambda p: p.relative_to(folder).as_posix()  # noqa: E731
    fig_success = plots.success_and_spl(per_world, ranked, order, figures / "success_spl.png")
    fig_time = plots.success_within_time(rows, order, figures / "success_vs_time.png")
    fig_time_worlds = plots.success_within_time_by_world(rows, order,
                                                         figures / "success_vs_time_by_world.png")
    traj_figs: list[tuple[str, Path]] = []
    worlds = list(per_world)
    for world in worlds[:MAX_TRAJECTORY_WORLDS]:
        path = plots.trajectories(world, [r for r in rows if r["world"] == world], runs, order,
                                  figures / f"trajectories_{_file_word(world)}.png")
        if path is not None:
            traj_figs.append((world, path))

    md = [f"# nav-bench report: {', '.join(run.name for run in runs)}", ""]
    md += ["## Runs", "", _runs_section(runs), ""]
    md += ["## Overall ranking", "",
           "Success first, then SPL. Success: share of episodes that reached the goal, with a "
           "95% Wilson interval. SPL: mean over all episodes (failures count 0), 95% bootstrap "
           "interval. Time to goal and path length: means over episodes that reached the goal. "
           f"Outcomes: {' / '.join(OUTCOMES)}.", ""]
    md.append(_md_table(
        ["rank", "parameter set", "planner", "episodes", "success", "SPL", "time to goal (s)",
         "path (m)", "re-plans", "collisions", "outcomes"],
        [[i, g.set, g.planner, g.n, _ci(g.success, g.success_ci), _ci(g.spl, g.spl_ci),
          _f(g.time_s, 1), _f(g.path_m), _f(g.replans, 1), _f(g.collisions, 1),
          _outcome_text(g.outcomes)] for i, g in enumerate(ranked, start=1)]))
    md += ["", f"![success and SPL per world]({rel(fig_success)})", ""]
    if fig_time is not None:
        md += [f"![success within a time budget]({rel(fig_time)})", "",
               "Share of episodes that reached the goal within T simulated seconds: a slow "
               "planner rises late, a failing one stays low.", ""]
    if fig_time_worlds is not None:
        md += [f"![success within a time budget, per world]({rel(fig_time_worlds)})", ""]
    if pairs:
        md += ["## Paired comparisons", "",
               "Each pair played the same worlds, seeds and robot; differences are A − B with "
               "95% bootstrap intervals. Path length compares only episodes both reached; "
               "wins / ties / losses count episodes by SPL.", ""]
        md.append(_md_table(
            ["A", "B", "pairs", "ΔSPL", "both reached", "Δpath (m)", "A wins / ties / B wins"],
            [[p.a, p.b, p.pairs, _signed(p.d_spl, p.d_spl_ci), p.both_reached,
              _signed(p.d_path_m, p.d_path_ci, 2), f"{p.wins} / {p.ties} / {p.losses}"]
             for p in pairs]))
        md.append("")
    difficulty_rows = difficulty_table(rows, order, world_difficulties(rows, runs))
    if difficulty_rows:
        md += ["## By world difficulty", "",
               "Worlds split into thirds by each BARN difficulty measure (Perille et al. 2020, "
               "computed on the true map along the optimal path of a 0.18 m robot); cells: "
               "success rate (episodes). Tortuosity and dispersion grow with difficulty; "
               "clearance, passage width and visibility shrink.", ""]
        md.append(_md_table(["measure", "third", "range", "worlds", *order], difficulty_rows))
        md.append("")
    md += ["## Per world", ""]
    figs = dict(traj_figs)
    for world, stats in per_world.items():
        md += [f"### {world}", ""]
        md.append(_md_table(
            ["parameter set", "episodes", "success", "SPL", "time to goal (s)", "path (m)",
             "re-plans", "collisions", "min clearance (m)", "outcomes"],
            [[g.set, g.n, _ci(g.success, g.success_ci), _ci(g.spl, g.spl_ci), _f(g.time_s, 1),
              _f(g.path_m), _f(g.replans, 1), _f(g.collisions, 1), _f(g.min_clearance_m, 3),
              _outcome_text(g.outcomes)] for g in stats]))
        md.append("")
        if world in figs:
            md += [f"![trajectories on {world}]({rel(figs[world])})", ""]
    if len(worlds) > MAX_TRAJECTORY_WORLDS:
        md += [f"Trajectory figures are drawn for the first {MAX_TRAJECTORY_WORLDS} of "
               f"{len(worlds)} worlds.", ""]
    errors = [r for r in rows if r.get("outcome") == "error"]
    if errors:
        md += ["## Episodes that ended in an error", ""]
        md.append(_md_table(["run", "episode", "error"],
                            [[r["run"], r.get("job_id", "?"), _last_line(r.get("error"))]
                             for r in errors]))
        md.append("")
    md += ["Numbers per (parameter set, world) are in `summary.csv`.", ""]
    report = folder / "report.md"
    report.write_text("\n".join(md), encoding="utf-8")
    return report


def _last_line(text: str | None) -> str:
    lines = [x.strip() for x in (text or "").strip().splitlines() if x.strip()]
    return (lines[-1] if lines else "?")[:200]


def _file_word(text: str) -> str:
    from nav_bench.suite import slug

    return slug(text)
