"""A live map of an episode, redrawn every ``every_s`` of simulated time (the paper: 0.5 s).

``LiveView`` shows the true map faint, the planner's occupancy grid (when its
``debug_state()`` has ``pmo``), the trajectory so far, the robot, the chain of re-plans so far
(numbered breakpoints, EO stops marked apart from re-plans on a blocked path, as the paper's
Fig. 4) and the latest re-plan's neighbours coloured by risk. It draws to a window (``show=True``, needs an interactive
matplotlib backend) and/or to an animated file without a screen (``save=`` ``.gif`` via
Pillow, ``.mp4`` via ffmpeg: on the PATH, or the imageio-ffmpeg wheel of the ``[video]``
extra).

The episode calls :meth:`LiveView.update` every control cycle and :meth:`LiveView.close`
at the end. Memory: GIF frames are kept (palette-compressed, ~0.1-0.2 MB each at the
default size) until :meth:`close` writes the file; MP4 frames stream to ffmpeg.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Circle

from nav_bench.errors import InputError
from nav_bench.interface import NO_RISK_COLOR, RISK_COLORS, GridState, ReplanEvent
from nav_bench.reporting.episode_plot import (
    BREAKPOINT_STYLE,
    CHAIN_COLOR,
    TRUE_COLOR,
    breakpoints_by_trigger,
    chain_vertices,
)
from nav_bench.specs import WorldSpec, default_robot_radius
from nav_bench.world.draw import draw_world

NON_INTERACTIVE = {"agg", "pdf", "ps", "svg", "pgf", "cairo", "template"}


def ffmpeg_exe() -> str | None:
    """ffmpeg on the PATH, else the binary of the imageio-ffmpeg wheel (the [video] extra)."""
    found = shutil.which("ffmpeg")
    if found:
        return found
    try:
        import imageio_ffmpeg
    except ImportError:
        return None
    try:
        return imageio_ffmpeg.get_ffmpeg_exe()
    except RuntimeError:  # the wheel has no binary for this platform
        return None


class LiveView:
    """Redraws the episode every ``every_s`` simulated seconds to a window and/or a file.

    Args:
        world: the world being played (its true map is drawn faint).
        every_s: simulated seconds between frames.
        show: open a matplotlib window (interactive backend needed, else :class:`InputError`).
        save: ``.gif`` or ``.mp4`` path for an animation, or None.
        fps: playback frames per second of the file (default ``1 / every_s``: real time).
        robot_radius: m, for the robot's outline (default: the default robot's).
        dpi, size_in: frame resolution and size (inches, longest side).
    """

    def __init__(self, world: WorldSpec, every_s: float = 0.5, show: bool = False,
                 save: str | Path | None = None, *, fps: float | None = None,
                 robot_radius: float | None = None, dpi: int = 80, size_in: float = 6.0) -> None:
        if every_s <= 0:
            raise InputError(f"live view: every_s must be > 0, got {every_s!r}")
        self.world, self.every_s = world, float(every_s)
        self.save = Path(save) if save is not None else None
        self.fps = float(fps) if fps else 1.0 / self.every_s
        self.dpi = dpi
        self.frames_drawn = 0
        self._next_t = -np.inf
        self._trail: list[tuple[float, float]] = []
        self._last: tuple[float, np.ndarray, dict[str, Any]] | None = None
        self._plan: ReplanEvent | None = None
        self._plans: list[ReplanEvent] = []  # every re-plan so far: the chain
        self._numbered = 0  # breakpoints already given their number
        self._drawn_since_update = False
        self._gif_frames: list[Any] = []
        self._writer: Any = None
        if self.save is not None and self.save.suffix.lower() not in (".gif", ".mp4"):
            raise InputError(f"live view: --record expects a .gif or .mp4 file, got {str(self.save)!r}")
        ffmpeg = None
        if self.save is not None and self.save.suffix.lower() == ".mp4":
            ffmpeg = ffmpeg_exe()
            if ffmpeg is None:
                raise InputError("live view: writing .mp4 needs ffmpeg: pip install "
                                 "\"nav-bench[video]\" (or put ffmpeg on the PATH), or record "
                                 "a .gif instead")
        self._make_figure(show, size_in, default_robot_radius() if robot_radius is None else robot_radius)
        if self.save is not None:
            self.save.parent.mkdir(parents=True, exist_ok=True)
            if self.save.suffix.lower() == ".mp4":
                import matplotlib
                from matplotlib.animation import FFMpegWriter

                matplotlib.rcParams["animation.ffmpeg_path"] = ffmpeg
                self._writer = FFMpegWriter(fps=self.fps)
                self._writer.setup(self.fig, str(self.save), dpi=self.dpi)

    # -- figure --------------------------------------------------------------------------------
    def _make_figure(self, show: bool, size_in: float, robot_radius: float) -> None:
        sx, sy = self.world.size
        figsize = (size_in * sx / max(sx, sy) + 0.3, size_in * sy / max(sx, sy) + 0.5)
        self.show = show
        if show:
            import matplotlib
            import matplotlib.pyplot as plt

            if matplotlib.get_backend().lower() in NON_INTERACTIVE:
                raise InputError(f"live view: the matplotlib backend {matplotlib.get_backend()!r} "
                                 "cannot open a window; set MPLBACKEND (e.g. TkAgg, QtAgg) or "
                                 "record to a file instead")
            self.fig = plt.figure(figsize=figsize)
            plt.show(block=False)
        else:
            from matplotlib.backends.backend_agg import FigureCanvasAgg

            self.fig = Figure(figsize=figsize)
            FigureCanvasAgg(self.fig)
        ax = self.ax = self.fig.add_axes((0.09, 0.08, 0.88, 0.84))
        draw_world(ax, self.world, faint=True)
        self._image = ax.imshow(np.zeros((1, 1)), origin="lower", cmap="Greys", vmin=0, vmax=100,
                                alpha=0.85, interpolation="nearest", zorder=0, visible=False)
        (self._path,) = ax.plot([], [], lw=1.4, color=TRUE_COLOR, zorder=5)
        self._robot = Circle((0, 0), robot_radius, facecolor="none", edgecolor=TRUE_COLOR, lw=1.5,
                             zorder=6)
        ax.add_patch(self._robot)
        (self._heading,) = ax.plot([], [], lw=1.5, color=TRUE_COLOR, zorder=6)
        (self._target,) = ax.plot([], [], ls=":", lw=1.0, color="black", zorder=6)
        self._neighbours = ax.scatter([], [], s=18, zorder=7)
        (self._chain,) = ax.plot([], [], lw=0.8, color=CHAIN_COLOR, zorder=6)
        self._breakpoints = {
            trigger: ax.scatter([], [], s=26, marker=st["marker"], facecolors=st["facecolor"],
                                edgecolors=st["edgecolor"], linewidths=0.7, zorder=8)
            for trigger, st in BREAKPOINT_STYLE.items()}
        (self._chosen,) = ax.plot([], [], marker="*", ms=11, mec="black", mfc="#2ca02c", ls="none",
                                  zorder=8)
        self._title = ax.set_title("t = 0.0 s", fontsize=10)

    # -- the episode's calls ---------------------------------------------------------------------
    def update(self, t: float, true_pose: np.ndarray, planner_state: dict[str, Any] | None,
               events: list[Any] | None = None) -> None:
        """One control cycle.

        Args:
            t: simulated time, s. true_pose: (3,) x, y, yaw.
            planner_state: the planner's ``debug_state()`` now (may be empty).
            events: the events emitted since the previous call ({kind, t, data} dicts or
                PlannerEvent objects); the latest ``replan`` is drawn.
        """
        pose = np.asarray(true_pose, dtype=float)
        self._trail.append((float(pose[0]), float(pose[1])))
        for e in events or ():
            plan = ReplanEvent.from_event(e)
            if plan is not None:
                self._plan = plan
                self._plans.append(plan)
        self._last = (float(t), pose, dict(planner_state or {}))
        self._drawn_since_update = False
        if t + 1e-9 >= self._next_t:
            self._draw()
            self._next_t = (np.floor(t / self.every_s + 1e-9) + 1) * self.every_s

    def close(self) -> None:
        """Draw the final state (if not drawn yet) and finish the file. Safe to call twice."""
        if self._last is not None and not self._drawn_since_update:
            self._draw()
        if self._writer is not None:
            self._writer.finish()
            self._writer = None
        elif self.save is not None and self._gif_frames:
            first, *rest = self._gif_frames
            first.save(self.save, save_all=True, append_images=rest, loop=0,
                       duration=round(1000.0 / self.fps), disposal=1)
            self._gif_frames = []
        if self.show:
            import matplotlib.pyplot as plt

            plt.close(self.fig)
            self.show = False

    def __enter__(self) -> LiveView:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- drawing -------------------------------------------------------------------------------
    def _draw(self) -> None:
        assert self._last is not None
        t, pose, state = self._last
        grids = GridState.from_state(state)
        if grids is not None:
            self._image.set_data(grids.pmo)
            self._image.set_extent(grids.extent)
            self._image.set_visible(True)
        trail = np.asarray(self._trail)
        self._path.set_data(trail[:, 0], trail[:, 1])
        x, y, yaw = pose[:3]
        self._robot.center = (x, y)
        r = self._robot.radius
        self._heading.set_data([x, x + 1.6 * r * np.cos(yaw)], [y, y + 1.6 * r * np.sin(yaw)])
        target = state.get("target")
        self._target.set_data(*(([x, target[0]], [y, target[1]]) if target is not None else ([], [])))
        if self._plan is not None:
            pts = np.asarray(self._plan.neighbours, dtype=float)
            colors = [RISK_COLORS.get(v, NO_RISK_COLOR) for v in self._plan.risk]
            cand = self._plan.candidate or (True,) * len(pts)
            self._neighbours.set_offsets(pts)
            self._neighbours.set_edgecolors(colors)
            self._neighbours.set_facecolors([c if k else "none" for c, k in zip(colors, cand, strict=False)])
            chosen = self._plan.chosen
            self._chosen.set_data(*(([pts[chosen, 0]], [pts[chosen, 1]]) if chosen is not None else ([], [])))
            self._draw_chain()
        mode = state.get("mode")
        self._title.set_text(f"t = {t:.1f} s" + (f"   mode: {mode}" if mode else ""))
        self._drawn_since_update = True
        self.frames_drawn += 1
        if self.show:
            self.fig.canvas.draw()
            self.fig.canvas.flush_events()  # let the GUI paint without blocking the episode
        if self._writer is not None:
            self._writer.grab_frame()
        elif self.save is not None:
            self._grab_gif_frame()

    def _draw_chain(self) -> None:
        """The chain so far; breakpoints numbered as they come (all of the first 40, then every
        10th: numbers drawn once stay, so the rule cannot depend on the final count)."""
        chain = chain_vertices(self._plans)
        self._chain.set_data(chain[:, 0], chain[:, 1])
        for trigger, xy in breakpoints_by_trigger(self._plans).items():
            self._breakpoints[trigger].set_offsets(xy)
        for k in range(self._numbered + 1, len(self._plans) + 1):
            if k <= 40 or k % 10 == 0:
                bx, by = self._plans[k - 1].breakpoint
                self.ax.annotate(str(k), (bx, by), xytext=(3, 3), textcoords="offset points",
                                 fontsize=6, color=CHAIN_COLOR, zorder=9)
        self._numbered = len(self._plans)

    def _grab_gif_frame(self) -> None:
        from PIL import Image

        self.fig.canvas.draw()
        rgba = np.asarray(self.fig.canvas.buffer_rgba())
        # palette images: ~4x less memory than RGBA while frames wait for close()
        self._gif_frames.append(Image.fromarray(rgba[..., :3].copy()).quantize(
            colors=255, method=Image.Quantize.FASTOCTREE))
