"""Report figures (PNG, matplotlib Agg), drawn from stored rows and traces only.

* :func:`success_and_spl`: success rate and mean SPL per world and parameter set, grouped
  bars with 95% interval whiskers (Wilson for success, bootstrap for SPL);
* :func:`success_within_time`: share of episodes that reached the goal within T simulated
  seconds, T from 0 to the time limit, one curve per parameter set;
* :func:`trajectories`: for one world, the true trajectories of every parameter set over the
  true map;
* :func:`success_vs_smoothness`: success rate against integrated jerk and angle over length,
  one point per parameter set.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import matplotlib.ticker
import numpy as np

from nav_bench.reporting.runs import Run, load_trajectory, trace_path, world_of
from nav_bench.reporting.statistics import GroupStats, share_reached_within
from nav_bench.world.draw import draw_world

DPI = 110


def _colors(n: int) -> list[Any]:
    cmap = plt.get_cmap("tab10" if n <= 10 else "tab20")
    return [cmap(i % cmap.N) for i in range(n)]


def success_and_spl(per_world: dict[str, list[GroupStats]], overall: Sequence[GroupStats],
                    order: Sequence[str], path: Path) -> Path:
    """Grouped bars: one group per world (and "all worlds"), one bar per parameter set."""
    groups = [*per_world.items(), ("all worlds", list(overall))]
    colors = dict(zip(order, _colors(len(order)), strict=True))
    width = 0.8 / max(1, len(order))
    fig_w = min(24.0, max(6.0, 2.5 + 0.35 * len(groups) * max(2, len(order))) + 2.0)
    fig, axes = plt.subplots(2, 1, figsize=(fig_w, 6.5), sharex=True)
    for ax, what in zip(axes, ("success", "spl"), strict=True):
        for j, name in enumerate(order):
            xs, ys, lo, hi = [], [], [], []
            for i, (_, stats) in enumerate(groups):
                g = next((s for s in stats if s.set == name), None)
                if g is None or math.isnan(getattr(g, what)):
                    continue
                value, ci = (g.success, g.success_ci) if what == "success" else (g.spl, g.spl_ci)
                xs.append(i - 0.4 + width * (j + 0.5))
                ys.append(value)
                below, above = error_bar(value, ci)
                lo.append(below)
                hi.append(above)
            ax.bar(xs, ys, width=width * 0.95, color=colors[name], label=name,
                   yerr=[lo, hi], capsize=2, error_kw={"lw": 0.8, "alpha": 0.8})
        ax.set_ylim(0, 1.05)
        ax.set_ylabel("success rate" if what == "success" else "SPL (mean)")
        ax.grid(axis="y", alpha=0.3)
        ax.axvline(len(groups) - 1.5, color="grey", lw=0.6, ls=":")
    axes[1].set_xticks(range(len(groups)))
    axes[1].set_xticklabels([w for w, _ in groups], rotation=30 if len(groups) > 6 else 0,
                            ha="right" if len(groups) > 6 else "center")
    axes[0].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    axes[1].set_title("whiskers: 95% intervals, Wilson (success) and bootstrap (SPL)",
                      fontsize=8, loc="left")
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def _time_horizon(rows: Sequence[dict[str, Any]]) -> float:
    """The largest time limit (s) among the rows, or the longest episode if none is recorded."""
    limits = [r.get("time_limit_s") or (r.get("settings") or {}).get("time_s") for r in rows]
    times = [r.get("time_s") for r in rows if r.get("time_s") is not None]
    return float(max([x for x in limits if x] or times or [0.0]))


def _draw_within_time(ax: Any, rows: Sequence[dict[str, Any]], order: Sequence[str],
                      horizon: float, legend: bool) -> None:
    t = np.linspace(0.0, horizon, 400)
    for name, color in zip(order, _colors(len(order)), strict=True):
        mine = [r for r in rows if r["set"] == name]
        if mine:
            ax.step(t, share_reached_within(mine, t), where="post", color=color,
                    label=f"{name} (n={len(mine)})")
    ax.set_xlim(0, horizon)
    ax.set_ylim(0, 1.02)
    ax.grid(alpha=0.3)
    if legend:
        ax.legend(fontsize=8, loc="upper left")


def success_within_time(rows: Sequence[dict[str, Any]], order: Sequence[str],
                        path: Path) -> Path | None:
    """Share of each set's episodes that reached the goal within T, for T up to the limit."""
    horizon = _time_horizon(rows)
    if horizon <= 0:
        return None
    fig, ax = plt.subplots(figsize=(7.0, 4.2))
    _draw_within_time(ax, rows, order, horizon, legend=True)
    ax.set_xlabel("time budget T (simulated s)")
    ax.set_ylabel("share reached within T")
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def success_within_time_by_world(rows: Sequence[dict[str, Any]], order: Sequence[str],
                                 path: Path, max_worlds: int = 16) -> Path | None:
    """The same curve, one panel per world (the first ``max_worlds``): slow or failing, where."""
    horizon = _time_horizon(rows)
    worlds = sorted({r["world"] for r in rows})[:max_worlds]
    if horizon <= 0 or len(worlds) < 2:
        return None
    cols = min(4, len(worlds))
    nrows = -(-len(worlds) // cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(3.2 * cols, 2.5 * nrows + 0.6),
                             sharex=True, sharey=True, squeeze=False)
    for ax, world in zip(axes.flat, worlds, strict=False):
        _draw_within_time(ax, [r for r in rows if r["world"] == world], order, horizon, legend=False)
        ax.set_title(world, fontsize=9)
    for ax in axes.flat[len(worlds):]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("time budget T (s)")
    for ax in axes[:, 0]:
        ax.set_ylabel("reached within T")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=min(len(order), 4), fontsize=8,
               frameon=False)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def trajectories(world_name: str, rows: Sequence[dict[str, Any]], runs: Sequence[Run],
                 order: Sequence[str], path: Path) -> Path | None:
    """Every episode's true path on ``world_name``, coloured by parameter set, over the map.

    Ends are marked: a dot for reached, a cross for anything else. None if no trace exists.
    """
    by_name = {run.name: run for run in runs}
    paths = []
    for row in rows:
        xy = load_trajectory(trace_path(by_name[row["run"]], row))
        if xy is not None and len(xy):
            paths.append((row, xy))
    if not paths:
        return None
    world = world_of(rows, runs)
    if world is not None:
        sx, sy = world.size
    else:
        allxy = np.concatenate([xy for _, xy in paths])
        sx, sy = float(allxy[:, 0].max()) + 0.5, float(allxy[:, 1].max()) + 0.5
    scale = 6.5 / max(sx, sy)
    fig, ax = plt.subplots(figsize=(max(3.5, sx * scale) + 2.6, max(3.0, sy * scale) + 0.6))
    if world is not None:
        draw_world(ax, world, faint=True)
    colors = dict(zip(order, _colors(len(order)), strict=True))
    shown: set[str] = set()
    for row, xy in paths:
        name = row["set"]
        color = colors.get(name, "black")
        ax.plot(xy[:, 0], xy[:, 1], color=color, lw=1.0, alpha=0.75, zorder=3,
                label=None if name in shown else name)
        shown.add(name)
        ax.plot(xy[-1, 0], xy[-1, 1], marker="o" if row.get("success") else "x", ms=5,
                color=color, zorder=4, ls="none")
    ax.set_aspect("equal")
    ax.set_title(f"{world_name}: true trajectories (o reached, x not)", fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    keep = [(h, lab) for h, lab in zip(handles, labels, strict=True) if lab in colors]
    if keep:
        ax.legend(*zip(*keep, strict=True), fontsize=8, loc="upper left",
                  bbox_to_anchor=(1.01, 1.0), frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def error_bar(value: float, interval: tuple[float, float]) -> tuple[float, float]:
    """The (below, above) lengths of an error bar from ``value`` to its interval's ends: never
    negative (matplotlib refuses that), 0 for an unknown (NaN) end. At a success rate of 0 or 1
    the Wilson interval's end equals the value only up to rounding (1 - 1e-16)."""
    low, high = interval
    below = 0.0 if math.isnan(low) else max(0.0, value - low)
    above = 0.0 if math.isnan(high) else max(0.0, high - value)
    return below, above


def success_vs_smoothness(overall: Sequence[GroupStats], path: Path) -> Path | None:
    """Each parameter set as a point: success rate (y) against the smoothness of its successful
    episodes (x): integrated squared linear jerk (log scale) and angle over length. None when
    no set has a success with motion metrics."""
    sets = [g for g in overall
            if not math.isnan(g.motion.get("jerk_linear", math.nan))
            and not math.isnan(g.motion.get("curvature_per_m", math.nan))]
    if not sets:
        return None
    colors = _colors(len(sets))
    fig, axes = plt.subplots(1, 2, figsize=(12.5, 4.4), sharey=True)
    panels = (("jerk_linear", "integrated squared linear jerk (m²/s⁵), log scale", True),
              ("curvature_per_m", "angle over length (rad/m)", False))
    for ax, (key, label, log) in zip(axes, panels, strict=True):
        for g, color in zip(sets, colors, strict=True):
            x = g.motion[key]
            below, above = error_bar(g.success, g.success_ci)
            ax.errorbar([x], [g.success], yerr=[[below], [above]],
                        fmt="o", color=color, ms=7, capsize=2, lw=0.8, label=g.set)
        if log and all(g.motion[key] > 0 for g in sets):
            ax.set_xscale("log")
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())  # labels overlap
        ax.set_xlabel(label)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("success rate (95% Wilson interval)")
    axes[0].set_ylim(-0.03, 1.05)
    axes[0].set_title("smoothness of the successful episodes; left and up is better", fontsize=8,
                      loc="left")
    axes[1].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path
