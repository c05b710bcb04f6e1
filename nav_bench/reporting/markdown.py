"""``nav-bench report``: tables, comparisons and figures from stored results only.

Reads results folders (``episodes.jsonl``, ``run.json``, ``traces/``) and writes
``report.md``, ``summary.csv`` and ``figures/*.png``. Nothing is simulated again.

The statistics are in :mod:`nav_bench.reporting.statistics`, the figures in
:mod:`nav_bench.reporting.figures`.

With several folders, each parameter set is labelled ``<run>/<label>`` (run = folder name).
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any

from nav_bench.batch.suite import slug
from nav_bench.episode.motion import MOTION_FIELDS
from nav_bench.episode.protocol import rules_text
from nav_bench.episode.row import OUTCOMES
from nav_bench.errors import InputError
from nav_bench.reporting import figures as plots
from nav_bench.reporting.runs import Run, load_runs
from nav_bench.reporting.statistics import (
    GroupStats,
    difficulty_table,
    paired_comparisons,
    ranking,
    world_difficulties,
    world_table,
)
from nav_bench.specs import default_robot_radius

# summary.csv's map-quality columns (GroupStats.map_*; empty: no grid)
MAP_COLUMNS = ("map_episodes", "map_precision_mean", "map_recall_mean", "map_phantom_share_mean",
               "map_phantom_episodes")
MAX_TRAJECTORY_WORLDS = 24  # trajectory figures beyond this many worlds are left out



# --------------------------------------------------------------------------- loading


# --------------------------------------------------------------------------- tables


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
                "replans_mean", "collisions_mean", "min_clearance_m", "barn_score_mean",
                *MOTION_FIELDS, *MAP_COLUMNS])

    def num(x: float) -> str:
        return "" if math.isnan(x) else f"{x:.6g}"

    for g in [*(g for stats in per_world.values() for g in stats), *ranked]:
        w.writerow([g.set, g.planner, g.world, g.n, *(g.outcomes[k] for k in OUTCOMES),
                    num(g.success), num(g.success_ci[0]), num(g.success_ci[1]), num(g.spl),
                    num(g.spl_ci[0]), num(g.spl_ci[1]), num(g.time_s), num(g.path_m),
                    num(g.replans), num(g.collisions), num(g.min_clearance_m), num(g.barn_score),
                    *(num(g.motion[k]) for k in MOTION_FIELDS),
                    g.map_episodes, num(g.map_precision), num(g.map_recall),
                    num(g.map_phantom_share), g.map_phantom_episodes])
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
    table = _md_table(["run", "suite", "episodes", "status", "started", "host", "executor",
                       "nav-bench", "commit"], rows)
    rules = []
    for run in runs:
        stored = (run.meta.get("suite") or {}).get("protocol")
        text = (rules_text(stored) if stored else
                "protocol `nav_bench` (run stored before protocols were recorded in run.json)")
        rules.append(f"* {run.name}: {text}" if len(runs) > 1 else text)
    return table + "\n\nRules: " + ("\n".join(rules) if len(runs) == 1 else "\n\n" + "\n".join(rules))


# --------------------------------------------------------------------------- the report
def _motion_section(ranked: Sequence[GroupStats], figures: Path, rel: Callable[[Path], str]) -> list[str]:
    """The motion metrics per parameter set over all worlds, and success vs smoothness."""
    if all(math.isnan(v) for g in ranked for v in g.motion.values()):
        return []  # rows stored before the motion metrics existed
    digits = {"accel_mean_mps2": 3, "accel_max_mps2": 2, "jerk_linear": 1, "jerk_angular": 0,
              "curvature_per_m": 2, "time_near_obstacles_s": 1, "plan_ms_mean": 2, "plan_ms_p95": 2}
    header = {"accel_mean_mps2": "mean \\|a\\| (m/s²)", "accel_max_mps2": "max \\|a\\| (m/s²)",
              "jerk_linear": "∫j² lin (m²/s⁵)", "jerk_angular": "∫j² ang (rad²/s⁵)",
              "curvature_per_m": "angle/length (rad/m)", "time_near_obstacles_s": "time near (s)",
              "plan_ms_mean": "plan ms mean", "plan_ms_p95": "plan ms p95"}
    md = ["## Motion", "",
          "How the robot moved, averaged over the episodes that reached the goal (definitions and "
          "sources in the README, \"Motion metrics\"): mean and largest linear acceleration, "
          "integrated squared linear and angular jerk, angle over length, time with the robot's "
          "edge within the safety distance of geometry, and the planner's wall-clock compute "
          "time per control cycle.", ""]
    md.append(_md_table(["parameter set", "reached", *(header[k] for k in MOTION_FIELDS)],
                        [[g.set, round(g.success * g.n),
                          *(_f(g.motion[k], digits[k]) for k in MOTION_FIELDS)] for g in ranked]))
    fig = plots.success_vs_smoothness(ranked, figures / "success_vs_smoothness.png")
    if fig is not None:
        md += ["", f"![success vs smoothness]({rel(fig)})", "",
               "Up and to the left is better: more goals reached, with less jerk and less "
               "turning per metre."]
    return [*md, ""]


def _map_section(per_world: dict[str, list[GroupStats]], ranked: Sequence[GroupStats]) -> list[str]:
    """Map quality per world and parameter set (planners that build a grid), then overall."""
    groups = [*(g for stats in per_world.values() for g in stats), *ranked]
    if not any(g.map_episodes for g in groups):
        return []  # no planner kept a grid, or rows stored before the fields existed
    md = ["## Map quality", "",
          "How the planner's final occupancy grid matches the true static map, over the cells "
          "its sonars observed (value ≠ 50); a cell is occupied above 65, a marked cell within "
          "one cell of a true obstacle counts as right (definitions: README, \"Map quality\"). "
          "Means over the episodes with a grid, reached or not. Phantom share: of the true free "
          "cells on the optimal path, the share the map marks occupied; the last column counts "
          "episodes with any such phantom wall on the route. Planners that keep no grid are "
          "left out.", ""]
    rows = [[g.world, g.set, g.map_episodes, _f(g.map_precision, 3), _f(g.map_recall, 3),
             _f(g.map_phantom_share, 3), f"{g.map_phantom_episodes} / {g.map_episodes}"]
            for g in groups if g.map_episodes]
    md.append(_md_table(["world", "parameter set", "episodes", "precision", "recall",
                         "phantom share", "phantom on route"], rows))
    return [*md, ""]


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
    scored = any(not math.isnan(g.barn_score) for g in ranked)
    md.append(_md_table(
        ["rank", "parameter set", "planner", "episodes", "success", "SPL",
         *(["BARN score"] if scored else []), "time to goal (s)",
         "path (m)", "re-plans", "collisions", "outcomes"],
        [[i, g.set, g.planner, g.n, _ci(g.success, g.success_ci), _ci(g.spl, g.spl_ci),
          *([_f(g.barn_score, 3)] if scored else []),
          _f(g.time_s, 1), _f(g.path_m), _f(g.replans, 1), _f(g.collisions, 1),
          _outcome_text(g.outcomes)] for i, g in enumerate(ranked, start=1)]))
    if scored:
        md += ["", "BARN score: mean of `barn_score` = success x OT / clip(AT, 2 OT, 8 OT) over "
               "all episodes (failures 0; 0.5 is the best possible)."]
    md += ["", f"![success and SPL per world]({rel(fig_success)})", ""]
    md += _motion_section(ranked, figures, rel)
    md += _map_section(per_world, ranked)
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
               f"computed on the true map along the optimal path of a {default_robot_radius():g} m "
               "robot); cells: "
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
    return slug(text)
