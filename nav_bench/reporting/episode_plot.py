"""One episode as a figure: the true map, the trajectory and, for EO/PC, its grids and re-plans.

Reads only a trace (any object with the attributes of :class:`nav_bench.episode.Trace`:
``t``, ``true_pose``, ``odom_pose``, ``events``, ``planner_state``, ``world`` and
optionally ``row``), never the simulator. For a planner whose final ``debug_state()`` has
``pmo``/``pmt`` grids (EO/PC) the figure has two panels: the occupancy grid PMO with every
breakpoint and its neighbours coloured by risk index, and the visit grid PMT.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import PatchCollection
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from nav_bench.interface import (
    NO_RISK_COLOR,
    REPLAN,
    RISK_COLORS,
    GridState,
    PlannerEvent,
    ReplanEvent,
)
from nav_bench.specs import WorldSpec
from nav_bench.world.draw import draw_world, obstacle_patches

TRUE_COLOR, ODOM_COLOR = "#1f4e9c", "#e377c2"
CHAIN_COLOR = "#111111"
# How each kind of breakpoint is marked (paper, Fig. 4): where EO stopped the robot, and where PC
# ran without a stop (Pi reached with the straight path to the goal blocked on PMO)
BREAKPOINT_STYLE = {
    "eo_stop": {"marker": "s", "facecolor": "#d62728", "edgecolor": "black", "label": "breakpoint: EO stop"},
    "blocked_path": {"marker": "D", "facecolor": "white", "edgecolor": "black",
                     "label": "breakpoint: PC, path blocked (no stop)"},
}
MAX_NEIGHBOUR_SETS = 40  # neighbours are drawn for the last this-many re-plans (more only clutter)


def replans(events: Iterable[Any]) -> list[ReplanEvent]:
    """Every ``replan`` event that carries a breakpoint and neighbours (EO/PC's), in order."""
    return [plan for plan in map(ReplanEvent.from_event, events) if plan is not None]


def chain_vertices(plans: list[ReplanEvent]) -> np.ndarray:
    """(2N, 2) the planned path as a chain: breakpoint 1, Pi 1, breakpoint 2, Pi 2, ... (m).

    After a re-plan the path is breakpoint -> Pi -> goal; the chain joins each Pi to the next
    breakpoint, which is Pi itself (a blocked-path breakpoint) or where EO stopped the robot
    on the way on. Re-plans without a chosen point are skipped.
    """
    pts: list[tuple[float, float]] = []
    for plan in plans:
        if plan.chosen is not None:
            pts += [plan.breakpoint, plan.neighbours[plan.chosen]]
    return np.asarray(pts, dtype=float).reshape(-1, 2)


def label_step(n: int) -> int:
    """Number every k-th breakpoint so that at most about 40 numbers are drawn."""
    return max(1, -(-n // 40))


def draw_chain(ax: Axes, plans: list[ReplanEvent], marker_size: float = 16,
               numbers: bool = True) -> None:
    """The chain of breakpoints as the paper's Fig. 4 draws it: the segments breakpoint -> Pi
    -> next breakpoint, each breakpoint numbered in order and marked by what made PC run
    (EO stop: filled square; path blocked without a stop: hollow diamond)."""
    chain = chain_vertices(plans)
    if len(chain):
        ax.plot(chain[:, 0], chain[:, 1], color=CHAIN_COLOR, lw=0.8, zorder=6)
    for trigger, xy in breakpoints_by_trigger(plans).items():
        style = BREAKPOINT_STYLE[trigger]
        ax.scatter(xy[:, 0], xy[:, 1], s=marker_size * 1.6, marker=style["marker"],
                   facecolors=style["facecolor"], edgecolors=style["edgecolor"], linewidths=0.7,
                   zorder=8)
    if not numbers:
        return
    step = label_step(len(plans))
    for k, plan in enumerate(plans, start=1):
        if k % step == 0 or k == 1 or k == len(plans):
            ax.annotate(str(k), tuple(plan.breakpoint), xytext=(3, 3), textcoords="offset points",
                        fontsize=6, zorder=9, color=CHAIN_COLOR)


def breakpoints_by_trigger(plans: list[ReplanEvent]) -> dict[str, np.ndarray]:
    """(N, 2) breakpoints (m) per kind of breakpoint in ``BREAKPOINT_STYLE``, in order; an
    unknown trigger is drawn as an EO stop."""
    xy: dict[str, list] = {trigger: [] for trigger in BREAKPOINT_STYLE}
    for plan in plans:
        xy[plan.trigger if plan.trigger in xy else "eo_stop"].append(plan.breakpoint)
    return {trigger: np.asarray(points, dtype=float).reshape(-1, 2) for trigger, points in xy.items()}


def draw_outlines(ax: Axes, world: WorldSpec) -> None:
    """Thin outlines of the true static obstacles: visible over the planner's grids."""
    ax.add_collection(PatchCollection(obstacle_patches(world), facecolor="none", edgecolor="#3b3b3b", lw=0.7,
                                      zorder=2))


def draw_pmo(ax: Axes, grids: GridState, alpha: float = 0.9) -> Any:
    """PMO as grey levels: white free, mid-grey unknown, black occupied."""
    return ax.imshow(grids.pmo, origin="lower", extent=grids.extent,
                     cmap="Greys", vmin=0, vmax=100, alpha=alpha, interpolation="nearest", zorder=0)


def draw_pmt(ax: Axes, grids: GridState) -> Any:
    """PMT visit counts on a log colour scale; never-visited cells transparent."""
    counts = np.asarray(grids.pmt, dtype=float)
    masked = np.ma.masked_less_equal(counts, 0)
    vmax = max(2.0, float(counts.max()))
    return ax.imshow(masked, origin="lower", extent=grids.extent, cmap="viridis",
                     norm=LogNorm(vmin=1, vmax=vmax), interpolation="nearest", zorder=3)


def draw_replans(ax: Axes, plans: list[ReplanEvent], marker_size: float = 16) -> None:
    """The chain of breakpoints (:func:`draw_chain`) and, for the last ``MAX_NEIGHBOUR_SETS``
    re-plans, the neighbours coloured by risk (hollow: not a candidate) and the choice (star)."""
    draw_chain(ax, plans, marker_size)
    for plan in plans[-MAX_NEIGHBOUR_SETS:]:
        pts = np.asarray(plan.neighbours, dtype=float)
        risk = plan.risk or (100,) * len(pts)
        cand = plan.candidate or (True,) * len(pts)
        colors = [RISK_COLORS.get(r, NO_RISK_COLOR) for r in risk]
        for filled in (True, False):
            sel = [i for i in range(len(pts)) if bool(cand[i]) == filled]
            if not sel:
                continue
            ax.scatter(pts[sel, 0], pts[sel, 1], s=marker_size, linewidths=0.9, zorder=6,
                       facecolors=[colors[i] for i in sel] if filled else "none",
                       edgecolors=[colors[i] for i in sel])
        if plan.chosen is not None:
            cx, cy = pts[plan.chosen]
            ax.scatter([cx], [cy], s=marker_size * 4, marker="*", facecolors=colors[plan.chosen],
                       edgecolors="black", linewidths=0.6, zorder=7)


def draw_paths(ax: Axes, trace: Any, light: bool = False) -> None:
    """True trajectory (solid) and odometry estimate (dashed); ``light`` for over a colour map."""
    true = np.asarray(trace.true_pose)
    odom = np.asarray(getattr(trace, "odom_pose", None) if getattr(trace, "odom_pose", None)
                      is not None else np.zeros((0, 3)))
    alpha, scale = (0.45, 0.5) if light else (1.0, 1.0)
    if len(odom):
        ax.plot(odom[:, 0], odom[:, 1], ls="--", lw=1.0 * scale, color=ODOM_COLOR, alpha=alpha,
                zorder=4)
    if len(true):
        ax.plot(true[:, 0], true[:, 1], lw=1.6 * scale, color=TRUE_COLOR, alpha=alpha, zorder=5)
        ax.plot([true[-1, 0]], [true[-1, 1]], marker="o", ms=5, color=TRUE_COLOR, zorder=5)


def episode_title(trace: Any) -> str:
    """``world - planner: outcome, time, path, re-plans`` from the row (or the trace alone)."""
    row = getattr(trace, "row", None) or {}
    world = row.get("world") or getattr(trace.world, "name", None) or "world"
    planner = row.get("planner", "planner")
    outcome = row.get("outcome", "?")
    t = row.get("time_s", float(np.asarray(trace.t)[-1]) if len(trace.t) else 0.0)
    true = np.asarray(trace.true_pose)
    length = row.get("path_length_m",
                     float(np.hypot(*np.diff(true[:, :2], axis=0).T).sum()) if len(true) > 1 else 0.0)
    n_replans = row.get("replans", sum(PlannerEvent.of(e).kind == REPLAN for e in trace.events))
    seed = f", seed {row['seed']}" if "seed" in row else ""
    events = row.get("events") or {}
    stops = events.get("replan.eo_stop")
    split = (f" ({stops} at EO stops, {events.get('replan.blocked_path', 0)} on a blocked path)"
             if stops is not None or "replan.blocked_path" in events else "")
    return (f"{world} - {planner}{seed}: {outcome} after {t:.1f} s, "
            f"path {length:.1f} m, {n_replans} re-plans{split}")


def legend_handles(has_grids: bool, has_plans: bool) -> list[Line2D]:
    handles = [
        Line2D([], [], color=TRUE_COLOR, lw=1.6, label="trajectory (true)"),
        Line2D([], [], color=ODOM_COLOR, lw=1.0, ls="--", label="trajectory (odometry)"),
        Line2D([], [], color="#1f77b4", marker="o", ls="none", label="start"),
        Line2D([], [], color="#d62728", marker="*", ms=10, ls="none", label="goal"),
    ]
    if has_plans:
        handles += [
            *[Line2D([], [], marker=st["marker"], mfc=st["facecolor"], mec=st["edgecolor"], color="black",
                     ls="none", label=st["label"]) for st in BREAKPOINT_STYLE.values()],
            Line2D([], [], color=CHAIN_COLOR, lw=0.8, label="planned path: breakpoint -> Pi (numbered)"),
            *[Line2D([], [], color=c, marker="o", ls="none", label=f"neighbour, risk {r}")
              for r, c in RISK_COLORS.items()],
            Line2D([], [], color=NO_RISK_COLOR, marker="o", mfc="none", ls="none",
                   label="not a candidate (blocked / tried)"),
            Line2D([], [], color="black", marker="*", mfc="#2ca02c", ms=10, ls="none",
                   label="chosen point Pi"),
        ]
    if has_grids:
        handles += [Line2D([], [], color="#808080", marker="s", ls="none", ms=8,
                           label="PMO (white free, black occupied)"),
                    Line2D([], [], color="#3b3b3b", marker="s", mfc="none", ls="none", ms=8,
                           label="true obstacles")]
    return handles


def plot_episode(trace: Any, path: str | Path, title: str | None = None, dpi: int = 150) -> Path:
    """Draw one episode to ``path`` (any format matplotlib writes: .png, .pdf, .svg).

    Returns the path written.
    """
    grids = GridState.from_state(getattr(trace, "planner_state", None))
    has_grids = grids is not None
    plans = replans(trace.events)
    sx, sy = trace.world.size
    width, height = 5.2 * sx / max(sx, sy), 5.2 * sy / max(sx, sy)  # inches per panel
    ncols = 2 if grids is not None and grids.pmt is not None else 1
    fig = Figure(figsize=(ncols * (width + 0.7), height + 1.5), layout="constrained")
    axes = fig.subplots(1, ncols, squeeze=False)[0]

    ax = axes[0]
    if grids is not None:
        draw_pmo(ax, grids)
        draw_outlines(ax, trace.world)
    draw_world(ax, trace.world, faint=True)
    draw_paths(ax, trace)
    draw_replans(ax, plans, marker_size=16 if len(plans) <= 12 else 9)
    if len(plans) > MAX_NEIGHBOUR_SETS:
        ax.text(0.01, 0.01, f"neighbours of the last {MAX_NEIGHBOUR_SETS} of {len(plans)} re-plans",
                transform=ax.transAxes, fontsize=7, zorder=10)
    ax.set_title("occupancy PMO and re-plans" if has_grids else "trajectory", fontsize=10)

    if ncols == 2:
        ax2 = axes[1]
        draw_world(ax2, trace.world, faint=True)
        image = draw_pmt(ax2, grids)
        draw_paths(ax2, trace, light=True)
        ax2.set_title("visits PMT (control cycles per cell)", fontsize=10)
        fig.colorbar(image, ax=ax2, shrink=0.8, label="cycles in cell")

    fig.suptitle(title or episode_title(trace), fontsize=11)
    fig.legend(handles=legend_handles(has_grids, bool(plans)), loc="outside lower center",
               ncol=4, fontsize=8, frameon=False)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    return path
