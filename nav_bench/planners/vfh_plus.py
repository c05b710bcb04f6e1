"""VFH+: the enhanced vector field histogram.

Reference: I. Ulrich and J. Borenstein, "VFH+: Reliable obstacle avoidance for fast mobile
robots", Proc. IEEE International Conference on Robotics and Automation (ICRA), 1998,
pp. 1572-1577. The certainty grid is the shared sonar map every map-building planner uses
(:class:`~nav_bench.mapping.occupancy.OccupancyGrid`) read as certainty
(:func:`certainty_from_occupancy`: occupancy 50..100 -> 0..``c_max``, unknown and free 0), in
place of HIMM's axis-only counts (Borenstein & Koren 1991), so the map plots and map-quality
figures compare like with like across planners.

Each cycle, on the cells of the active window (``window_radius`` m around the robot, or
the goal distance when that is shorter: VFH+ has no notion of a goal position, and a wall
just behind the goal would otherwise close the goal's sector for good):

1. **Primary polar histogram**: a cell at distance ``d`` and bearing ``beta`` with certainty
   ``c`` has magnitude ``m = c^2 (a - b d^2)`` with ``a - b d_max^2 = 1`` and enlarges over
   ``gamma = asin(r_rs / d)``, ``r_rs = radius + safety_distance``; sector ``k`` (centre
   ``k * alpha``, world frame) sums ``m`` of every cell with ``|k alpha - beta| <= gamma``.
2. **Binary histogram** with hysteresis: 1 above ``threshold_high``, 0 below
   ``threshold_low``, the previous value in between.
3. **Masked histogram**: the robot's turning circles at its current speed
   (``r = v / omega_max``, one left and one right) are blocked by cells with certainty above
   ``mask_certainty`` that lie within ``r + r_rs`` of the circle centre; directions beyond
   the first blocking cell on each side are unreachable.
4. **Valleys** (runs of free sectors) give candidate directions: the centre of a narrow
   valley; for a wide one (more than ``s_max`` sectors) the sectors ``s_max/2`` inside each
   border, plus the goal direction if it lies between them.
5. **Cost** ``mu1 D(c, goal) + mu2 D(c, heading) + mu3 D(c, previous choice)`` (D: angular
   difference in sectors); the cheapest candidate is the new direction.

**Cells seen through** (issue 12, ``results/baselines/vfh_s13/``): the shared grid blames a
sonar's whole echo arc and frees a cell only after many readings, so it stands up to a cell
proud of each obstacle; a 0.5-0.58 m gap between furniture, which the body (0.36 m) and the
enlarged robot (``2 r_rs`` = 0.46 m) fit through, closes in the histogram (the twelfth
session's six "implementation" timeouts, ``results/baselines/vfh_s12/``). The readings tell
which parts of those cells are free: a cone sonar's range says everything nearer inside its
cone is. So the window's cells are read through
:class:`~nav_bench.planners.carving.SeeThroughCarving`, the carving D* Lite's follower
measures its clearance against: each cell is ``CARVE_SUB`` x ``CARVE_SUB`` parts, and a part
seen through from two different views (or under the body) in the last few seconds is dropped.
A cell with a part dropped enters step 1 as its ``k`` kept parts, each a point with the
cell's certainty and ``1 / k`` of the cell's magnitude, enlarged by the same ``r_rs``: the
carving says where in the cell the obstacle can still be, not that it is less likely, so the
cell's evidence moves into its kept parts (a sector all of them cover gets the whole cell's
magnitude). A cell with every part kept is its centre, as in the paper (Ulrich & Borenstein
treat a certainty cell as a point at its centre and enlarge it by ``r_rs``): the enlargement
is unchanged, only where the evidence of an obstacle lies is finer. Gated alternatives
(``results/baselines/vfh_s13/``): ``1 / CARVE_SUB^2`` per part (the area's share) faded a
surface's last parts beside the robot until they closed no sector, and contacts rose; the
cell's whole magnitude on every kept part kept a gap closed by a few parts no view could see
through.
Beyond :data:`AREA_SHARE_BEYOND_M` (0.5 m) a kept part weighs only its area's share of the cell
(1/25; issue 12, ``results/baselines/vfh_s20/``): at range the sums pick the valley, and a cell's
last part left a few centimetres proud of a box, carrying the whole cell by the ``1 / k`` rule,
closed gaps the robot fits; nearer, the ``1 / k`` share (and within ``r_rs`` the whole cell)
keeps it off surfaces. Gated on 360 episodes no revision had played: reached 196 -> 206,
clutter 93 -> 112, episodes with a contact 18 -> 12, mazes 25 -> 16 (a corridor's carved far
wall weighs less at range).
The grid itself is unchanged (EO/PC read it with the paper's semantics).
``carve_seen_through: false`` gives whole cells.

**The window's size** (issue 12, ``results/baselines/vfh_s8/`` and ``vfh_s11/``): 1.2 m with
``b`` = 7.11, so ``a = 1 + b 1.2^2`` = 11.24 is the near weight the earlier 1.6 m window with
``b = 4`` had. The shared grid marks a wall certain along its whole length, so a wall across a
sector sums its cells within ``r_rs`` of the ray (five at 0.1 m cells) at any range; with the
1.6 m window five certain cells passed ``threshold_high`` 1.48 m away, and in a 1 m maze
corridor the way on closed before the turn at its end came into view: the only valley pointed
back, and the robot shuttled between the corridor's ends (tests: the corridor's end wall, the
L-turn). Now such a wall closes the sector from 1.13 m. The smaller window's sums are smaller,
so ``slow_density`` is 3000 (was 5000): a certain wall across the heading still stops the robot
1.1 m away. Side by side with the 1.6 m window over 280 episodes (the eighth session's gate and
the eleventh session's replication on new layouts and seeds) it reached 119 against 90, with
46 episodes with a contact against 48. ``window_radius: 1.6, distance_weight: 4,
slow_density: 5000`` gives the old behaviour.

Speed falls with the histogram density in the current heading (``v_max (1 - min(H, h_m)/h_m)``)
and with the heading error.

**No valley** (every sector above the thresholds): the 1998 paper gives no rule. The shared grid
marks a wall certain (``c_max``) along its whole length, two cells thick where the 25 deg
sonar arcs smear it, so beside a corner of a 1 m maze corridor every sector sums several
wall cells over ``threshold_high`` although the robot fits (tests: the dead-end corner).
The thresholds then relax (``threshold_high`` x 2, x 4 up to ``relax_max``, same turning
mask; sectors toward a cell within ``r_rs`` + one cell stay closed) until a valley opens,
and the robot creeps (``relaxed_speed``) along it: the least obstructed way. The Player
``vfh`` driver (a VFH+ implementation) does the like with speed: its obstacle cutoffs and
safety distance are linear in the speed, so a slow robot may come closer to obstacles.
Only if even that finds none does the robot stop and turn on the spot (``blocked`` event,
``stuck_reason`` NO_PATH) so its front sonars scan for one.

**Turns on the spot at speed** (issue 12, ``results/baselines/vfh_s17/`` to ``vfh_s20/``): the
paper's robot turns where it is told; this one's wheels ramp at 1 m/s^2, so a turn on the spot
commanded at speed ramps the outer wheel up and the inner one down, and the centre keeps its
speed until the outer wheel reaches the turn's (0.5 s for 5.8 rad/s from 0.25 m/s, 0.19 m of
roll). That roll was most of VFH+'s contacts. Two guards act only where the roll, modelled as
an arc (:func:`roll_arc`), would come within the body's radius of a window point: before the
turn begins, the robot brakes straight if the point is sure (:meth:`VFHPlus._spot_turn`);
otherwise the turn rate is capped at the rate whose outer wheel keeps the present speed, so
only the inner wheel reverses and the centre slows from the start (:meth:`VFHPlus._capped`,
any certainty). A roll into free space is left alone: it is what carries the robot into many
gaps, and braking or capping every roll lost them. Gated on 360 episodes no revision had
played (``vfh_s20``): reached 184 -> 196, episodes with a contact 56 -> 29.

What VFH+ cannot do, by its method: it has no memory and no look-ahead (VFH*, Ulrich &
Borenstein 2000, adds it), so a U trap, a comb's closed pocket or a maze's dead end holds
it in a back-and-forth the episode ends as ``stuck`` (oscillating); and a gap narrower than
``2 (radius + safety_distance)`` in the map (sonar arcs narrow a gap by a cell a side) is
never a valley unless the sonars see through the parts that narrow it (above). A reactive
method: no ``replan`` events.

Speed (issue 16; ``benchmarks/bench_vfh.py``, ``benchmarks/bench_planning.py``): a cycle reads
only the window's square of the live map and only its cells above 50 (:func:`read_window`),
with the cell-centre coordinates precomputed per row and column; each active cell's offset,
distance and bearing are computed once and shared by the histogram and the turning mask; a
cell is tested only against the sectors around its bearing (:func:`covered_sectors`, a margin
of one sector each side) instead of all ``n``. The 1998 paper precomputes each window cell's
angle and magnitude relative to the window's centre cell; here the robot's exact position is
used as before, so the tables hold what does not depend on it (cell centres), and the
histogram, hence every command, is the same bit for bit as testing every sector x cell
(tests: ``dense_polar_histogram``): each sector still sums its cells in window order.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass
from types import ModuleType
from typing import Any, ClassVar

import numpy as np

from nav_bench import compiled as compiled_code
from nav_bench.interface import Command, GridState, Observation, RobotInfo, StuckReason, wrap_angle
from nav_bench.mapping.grid import GridFrame
from nav_bench.mapping.occupancy import UNKNOWN, OccupancyGrid
from nav_bench.planners.base import Param, Planner
from nav_bench.planners.carving import UNDO_MODES, SeeThroughCarving
from nav_bench.planners.follow import STOP, OdometrySpeed, arrival_speed, limit


def sector_distance(a: np.ndarray | float, b: np.ndarray | float, n: int) -> np.ndarray:
    """Circular distance between sector positions (may be fractional), in sectors."""
    d = np.abs(np.asarray(a, dtype=float) - b) % n
    return np.minimum(d, n - d)


@functools.lru_cache(maxsize=8)
def sector_centres(n_sectors: int) -> np.ndarray:
    """(n,) world angle of each sector's centre, rad: ``k * 2 pi / n`` (read-only)."""
    centres = np.arange(n_sectors) * (2 * math.pi / n_sectors)
    centres.flags.writeable = False
    return centres


def certainty_from_occupancy(values: np.ndarray, c_max: float) -> np.ndarray:
    """VFH certainty (same shape, float 0..``c_max``) of occupancy values 0..100 (50 unknown).

    Only evidence of an obstacle counts: unknown and free cells (<= 50) are 0, a cell at 100
    is ``c_max``, linearly in between. VFH's certainty is evidence that a cell is occupied;
    the shared grid's log-odds above 0 is exactly that."""
    occ = np.asarray(values, dtype=float)
    return np.minimum(np.maximum((occ - 50.0) / 50.0, 0.0), 1.0) * c_max


@dataclass(frozen=True)
class ActiveWindow:
    """The cells of the active window with certainty > 0 as the robot sees them (or, after
    :meth:`carved`, the points that stand for them).

    Attributes:
        x, y: (M,) cell centres, m.
        certainty: (M,) certainty, 0..``c_max``.
        dx, dy: (M,) centre less the robot's position, m.
        dist: (M,) distance from the robot, m.
        rows, cols: (M,) the cells' grid indices (:func:`read_window`), or None.
        weight: (M,) each point's share of its cell's magnitude (1 for a whole cell, ``1 / k``
            for each of a cell's ``k`` kept parts), or None: all 1.
        area: (M,) each point's share of its cell's area (1 for a whole cell, ``1 / PARTS`` for
            a kept part), or None: all 1. The histogram weighs a part by it beyond
            :data:`AREA_SHARE_BEYOND_M` (:func:`window_histogram`).
    """

    x: np.ndarray
    y: np.ndarray
    certainty: np.ndarray
    dx: np.ndarray
    dy: np.ndarray
    dist: np.ndarray
    rows: np.ndarray | None = None
    cols: np.ndarray | None = None
    weight: np.ndarray | None = None
    area: np.ndarray | None = None

    @classmethod
    def of_cells(cls, cells_xy: np.ndarray, certainty: np.ndarray, xy: np.ndarray) -> ActiveWindow:
        """The window of cell centres (M, 2), m, with certainties (M,) seen from ``xy`` (2,)."""
        cells_xy = np.asarray(cells_xy, dtype=float).reshape(-1, 2)
        dx, dy = cells_xy[:, 0] - xy[0], cells_xy[:, 1] - xy[1]
        return cls(cells_xy[:, 0], cells_xy[:, 1], np.asarray(certainty, dtype=float), dx, dy,
                   np.hypot(dx, dy))

    def __len__(self) -> int:
        return len(self.dist)

    def bearings(self) -> np.ndarray:
        """(M,) world angle of each cell from the robot, rad."""
        return np.arctan2(self.dy, self.dx)

    def carved(self, kept: np.ndarray, parts: np.ndarray, xy: np.ndarray, compiled: bool = False) -> ActiveWindow:
        """The window with each cell some of whose parts were seen through replaced by its
        kept parts (``kept`` (M, P) bool, ``parts`` (M, P, 2) their centres, m: a
        :class:`~nav_bench.planners.carving.CarvedCells` of this window's cells), each part a
        point with its cell's certainty and ``1 / k`` of its cell's magnitude (``k`` its kept
        parts), in the cell's place in window order. A cell with every part kept stays its centre, as in the paper,
        so that with nothing seen through the window is this one (seen from ``xy`` (2,), m).
        ``compiled``: by :func:`nav_bench.planners.vfh_kernels.carved_points` (the same points)."""
        if compiled:
            if kept.all():
                return self
            x, y, certainty, weight, area, dx, dy, dist = load_kernels().carved_points(  # type: ignore[union-attr]
                self.x, self.y, self.certainty, kept, parts, float(xy[0]), float(xy[1]))
            return ActiveWindow(x, y, certainty, dx, dy, dist, weight=weight, area=area)
        whole = kept.all(axis=1)
        if whole.all():
            return self
        cell_i, part_i = np.nonzero(kept & ~whole[:, None])  # cell by cell
        cells = np.flatnonzero(whole)
        order = np.argsort(np.concatenate([cells, cell_i]), kind="stable")
        x = np.concatenate([self.x.take(cells), parts[cell_i, part_i, 0]])[order]
        y = np.concatenate([self.y.take(cells), parts[cell_i, part_i, 1]])[order]
        certainty = np.concatenate([self.certainty.take(cells), self.certainty.take(cell_i)])[order]
        share = 1.0 / np.maximum(kept.sum(axis=1), 1)  # the cell's magnitude shared by its kept parts
        weight = np.concatenate([np.ones(len(cells)), share.take(cell_i)])[order]
        area = np.concatenate([np.ones(len(cells)), np.full(len(cell_i), 1.0 / kept.shape[1])])[order]
        dx, dy = x - xy[0], y - xy[1]
        return ActiveWindow(x, y, certainty, dx, dy, np.hypot(dx, dy), weight=weight, area=area)


def load_kernels() -> ModuleType | None:
    """:mod:`nav_bench.planners.vfh_kernels`, or None when Numba cannot be imported
    (:func:`nav_bench.compiled.load`)."""
    return compiled_code.load("nav_bench.planners.vfh_kernels")


@functools.cache
def _load_compiled_code() -> None:
    """Call the window kernels once on a 3 x 3 grid (read-only, as the live map and the centre
    coordinates are), so that Numba loads their machine code now, once per process, not in the
    first control cycle."""
    frame = GridFrame(0.0, 0.0, 0.1, 3, 3)
    values = np.full((3, 3), 100, dtype=np.uint8)
    values.flags.writeable = False
    window = read_window(values, frame, np.array([0.15, 0.15]), 1.0, 1.0, compiled=True)
    kept = np.ones((len(window), 4), dtype=bool)
    kept[0, 0] = False
    window.carved(kept, np.zeros((len(window), 4, 2)), np.zeros(2), compiled=True)


@functools.lru_cache(maxsize=4)
def centre_coordinates(frame: GridFrame) -> tuple[np.ndarray, np.ndarray]:
    """(W,) x of each column's and (H,) y of each row's cell centres, m: the arithmetic of
    :meth:`GridFrame.cell_center` done once per frame (read-only)."""
    xs = frame.xmin + (np.arange(frame.cols).astype(float) + 0.5) * frame.cell
    ys = frame.ymin + (np.arange(frame.rows).astype(float) + 0.5) * frame.cell
    xs.flags.writeable = ys.flags.writeable = False
    return xs, ys


def window_box(frame: GridFrame, xy: np.ndarray, radius: float) -> tuple[int, int, int, int]:
    """(row0, row1, col0, col1): the grid's square holding the disc of ``radius`` m round
    ``xy`` (the robot's cell +- ``ceil(radius / cell) + 1``), clipped to the grid (empty,
    row1 == row0 or col1 == col0, when the robot is far outside it)."""
    h, w = frame.shape
    r0, c0 = frame.cell_of(float(xy[0]), float(xy[1]))
    n = math.ceil(radius / frame.cell) + 1
    rs, cs = max(r0 - n, 0), max(c0 - n, 0)
    return rs, max(min(r0 + n + 1, h), rs), cs, max(min(c0 + n + 1, w), cs)


def read_window(values: np.ndarray, frame: GridFrame, xy: np.ndarray, radius: float,
                c_max: float, box: tuple[int, int, int, int] | None = None,
                compiled: bool = False) -> ActiveWindow:
    """The cells with certainty > 0 within ``radius`` m of ``xy``, in row-major order: the
    active window of the occupancy ``values`` (H, W) 0..100 laid out by ``frame``. Reads only
    the window's square of the live map (``box``: :func:`window_box`, computed when not
    given), and converts only its cells above 50 (certainty > 0). ``compiled``: by
    :func:`nav_bench.planners.vfh_kernels.window_cells` (the same window bit for bit)."""
    x, y = float(xy[0]), float(xy[1])
    rs, re, cs, ce = window_box(frame, xy, radius) if box is None else box
    if rs >= re or cs >= ce:
        none, cells = np.zeros(0, dtype=np.intp), np.zeros(0)
        return ActiveWindow(cells, cells, cells, cells, cells, cells, none, none)
    if compiled:
        xs, ys = centre_coordinates(frame)
        rows, cols, cx, cy, cert, dx, dy, dist = load_kernels().window_cells(  # type: ignore[union-attr]
            values, np.array([rs, re, cs, ce], dtype=np.intp), xs, ys, x, y, float(radius), float(c_max), UNKNOWN)
        return ActiveWindow(cx, cy, cert, dx, dy, dist, rows, cols)
    square = values[rs:re, cs:ce]
    above = square > UNKNOWN
    rr, cc = np.divmod(above.ravel().nonzero()[0], ce - cs)  # row-major, as np.nonzero
    # certainty_from_occupancy of cells above 50: (occ - 50) / 50 > 0 needs no lower clip
    cert = np.minimum((square[above] - 50.0) / 50.0, 1.0)
    cert *= c_max
    xs, ys = centre_coordinates(frame)
    cx, cy = xs[cs:ce].take(cc), ys[rs:re].take(rr)
    dx, dy = cx - x, cy - y
    dist = np.hypot(dx, dy)
    rows, cols = rr + rs, cc + cs
    if dist.max(initial=0.0) > radius:  # the square's corners: keep the disc
        near = (dist <= radius).nonzero()[0]
        cx, cy, cert, dx, dy, dist, rows, cols = (a.take(near) for a in (cx, cy, cert, dx, dy, dist, rows, cols))
    return ActiveWindow(cx, cy, cert, dx, dy, dist, rows, cols)


def active_cells(values: np.ndarray, frame: GridFrame, xy: np.ndarray, radius: float,
                 c_max: float) -> tuple[np.ndarray, np.ndarray]:
    """Centres (M, 2) m and certainties (M,) of the cells with certainty > 0 within ``radius``
    m of ``xy``: the active window of the occupancy ``values`` (H, W) 0..100 laid out by
    ``frame`` (:func:`read_window`)."""
    window = read_window(values, frame, xy, radius, c_max)
    return np.stack([window.x, window.y], axis=1), window.certainty


@functools.lru_cache(maxsize=8)
def _sector_cycle(n_sectors: int) -> tuple[np.ndarray, np.ndarray]:
    """Sector numbers ``0..3n-1`` read modulo ``n``: (3n,) the sector and (3n,) its centre,
    rad (:func:`sector_centres`), for sector numbers shifted by ``n`` into ``[0, 3n)``."""
    sectors = np.tile(np.arange(n_sectors), 3)
    centres = np.tile(sector_centres(n_sectors), 3)
    sectors.flags.writeable = centres.flags.writeable = False
    return sectors, centres


def covered_sectors(beta: np.ndarray, gamma: np.ndarray, n_sectors: int) -> tuple[np.ndarray, np.ndarray]:
    """(sector, cell) index pairs with ``|k alpha - beta_i| <= gamma_i`` (circular): the sectors
    each cell's enlargement covers, from its bearing ``beta`` (M,) in ``[-pi, pi]`` and
    half-width ``gamma`` (M,) in ``[0, pi/2]``, rad; each pair once, by cell.

    Only the sectors around each cell are tested (from one sector below ``(beta - gamma) /
    alpha``), each with the arithmetic of a test of every sector: ``|((k alpha - beta + pi)
    mod 2 pi) - pi| <= gamma``, the ``mod`` done as one subtraction of ``2 pi`` where
    ``k alpha - beta + pi`` is in ``[2 pi, 4 pi)`` (the same number, as the remainder is exact)."""
    alpha = 2 * math.pi / n_sectors
    width = min(math.ceil(2 * float(gamma.max()) / alpha) + 3, n_sectors)
    sectors, centres = _sector_cycle(n_sectors)
    # sector numbers + n, in [0, 3n): beta - gamma >= -3 pi / 2
    first = np.floor((beta - gamma) / alpha).astype(np.intp)
    shifted = first[:, None] + np.arange(n_sectors - 1, n_sectors - 1 + width)  # (M, width)
    diff = centres.take(shifted)
    diff -= beta[:, None]
    diff += math.pi  # in [0, 4 pi)
    np.subtract(diff, 2 * math.pi, out=diff, where=diff >= 2 * math.pi)
    diff -= math.pi
    pairs = (np.abs(diff, out=diff) <= gamma[:, None]).ravel().nonzero()[0]
    return sectors.take(shifted.take(pairs)), pairs // width


# m: beyond this distance a kept part of a carved cell weighs its area's share of the cell (1/25),
# nearer its share of the cell's magnitude (1/k of its k kept parts; within r_rs the whole cell):
# the twentieth session's screen of 0 (every part by area, the thirteenth session's rejected
# share), 0.5 and 0.8 m on seen seeds (results/baselines/vfh_s20/)
AREA_SHARE_BEYOND_M = 0.5


def window_histogram(window: ActiveWindow, bearings: np.ndarray, n_sectors: int, r_rs: float,
                     d_max: float, b: float) -> np.ndarray:
    """(n,) primary polar histogram H^p of the ``window`` (its cells' ``bearings`` (M,), rad).

    A carved cell's kept parts share its magnitude (``window.weight``), except a part within
    ``r_rs``: that is the obstacle's surface inside the safety zone, and it carries its whole
    cell's magnitude, as the paper's cell within ``r_rs`` does over the +-90 deg it covers. A
    share there lets a convex corner beside the body, whose cell keeps only a few parts near it
    once its open parts stay carved, fall under the thresholds in the sectors the body would
    graze it along (``results/baselines/vfh_s18/``). Beyond :data:`AREA_SHARE_BEYOND_M` a kept
    part carries only its share of the cell's area (``window.area``): there the sums decide
    which valley the robot heads for, and a cell's last part left a few centimetres proud of a
    surface, with the whole cell's magnitude, closed gaps between boxes that the robot fits
    (``results/baselines/vfh_s20/``)."""
    if len(window) == 0:
        return np.zeros(n_sectors)
    dist = np.maximum(window.dist, 1e-6)
    mag = window.certainty ** 2 * (1.0 + b * (d_max ** 2 - dist ** 2))
    if window.weight is not None:  # parts of cells: their share of the cell's magnitude
        share = window.weight if window.area is None else np.where(dist < AREA_SHARE_BEYOND_M, window.weight,
                                                                   window.area)
        mag *= np.where(dist < r_rs, 1.0, share)
    gamma = np.arcsin(np.minimum(1.0, r_rs / dist))
    sector, cell = covered_sectors(bearings, gamma, n_sectors)
    # (n, M): each cell's magnitude in the sectors it covers (each pair once), 0 elsewhere;
    # each sector then sums its row in window order, zeros between: numpy's pairwise sum of
    # the full row, bit for bit what a test of every sector x cell gave
    m = len(window)
    spread = np.bincount(sector * m + cell, weights=mag.take(cell), minlength=n_sectors * m)
    return spread.reshape(n_sectors, m).sum(axis=1)


def polar_histogram(cells_xy: np.ndarray, certainty: np.ndarray, xy: np.ndarray, n_sectors: int,
                    r_rs: float, d_max: float, b: float) -> np.ndarray:
    """(n,) primary polar histogram H^p at ``xy`` from active cells (M, 2) (centres, m) with
    certainties (M,). Sector ``k`` is centred on world angle ``k * 2 pi / n``."""
    window = ActiveWindow.of_cells(cells_xy, certainty, xy)
    return window_histogram(window, window.bearings(), n_sectors, r_rs, d_max, b)


def binary_histogram(primary: np.ndarray, previous: np.ndarray, low: float, high: float) -> np.ndarray:
    """(n,) bool H^b: blocked above ``high``, free below ``low``, else as ``previous``."""
    # np.where(primary > high, True, np.where(primary < low, False, previous)) in fewer passes
    return (primary > high) | (previous & ~(primary < low))


def window_turning_limits(window: ActiveWindow, bearings: np.ndarray, pose: np.ndarray,
                          radius_turn: float, r_rs: float, mask_certainty: float) -> tuple[float, float]:
    """:func:`turning_limits` of the ``window`` (its cells' ``bearings`` (M,), rad)."""
    phi_r, phi_l = -math.pi, math.pi
    if len(window) == 0 or radius_turn <= 0:
        return phi_r, phi_l
    x, y, th = float(pose[0]), float(pose[1]), float(pose[2])
    s, c = math.sin(th), math.cos(th)
    strong = (window.certainty > mask_certainty).nonzero()[0]
    px, py = window.x.take(strong), window.y.take(strong)
    reach2 = (radius_turn + r_rs) ** 2
    # squared distances to the right and left circles' centres
    in_r = (px - (x + radius_turn * s)) ** 2 + (py - (y - radius_turn * c)) ** 2 < reach2
    in_l = (px - (x - radius_turn * s)) ** 2 + (py - (y + radius_turn * c)) ** 2 < reach2
    # bearings relative to the heading only of the cells within a circle (mostly none)
    within = (in_r | in_l).nonzero()[0]
    if len(within) == 0:
        return phi_r, phi_l
    rel = np.remainder(bearings.take(strong.take(within)) - th + math.pi, 2 * math.pi) - math.pi
    block_r = (rel < 0) & in_r.take(within)
    block_l = (rel > 0) & in_l.take(within)
    if block_r.any():
        phi_r = float(rel[block_r].max())
    if block_l.any():
        phi_l = float(rel[block_l].min())
    return phi_r, phi_l


def turning_limits(cells_xy: np.ndarray, certainty: np.ndarray, pose: np.ndarray, radius_turn: float,
                   r_rs: float, mask_certainty: float) -> tuple[float, float]:
    """(phi_right, phi_left): the reachable directions relative to the heading, rad, are those
    in ``(phi_right, phi_left)``; ``(-pi, pi)`` when nothing blocks the turning circles."""
    window = ActiveWindow.of_cells(cells_xy, certainty, np.asarray(pose[:2], dtype=float))
    return window_turning_limits(window, window.bearings(), pose, radius_turn, r_rs, mask_certainty)


def masked_histogram(binary: np.ndarray, heading: float, phi_r: float, phi_l: float) -> np.ndarray:
    """(n,) bool H^m: blocked if H^b is, or if the sector is outside ``(phi_r, phi_l)``."""
    if not (phi_r > -math.pi or phi_l < math.pi):  # nothing out of reach
        return binary.copy()
    rel = np.remainder(sector_centres(len(binary)) - heading + math.pi, 2 * math.pi) - math.pi
    return binary | ~((rel > phi_r) & (rel < phi_l))


def candidate_directions(masked: np.ndarray, k_target: float, s_max: int) -> list[float]:
    """Candidate sector positions from the valleys of ``masked`` (True = blocked).

    A valley is a circular run of free sectors from ``k_r`` (clockwise border) to ``k_l``.
    Narrow (``<= s_max`` sectors): its centre. Wide: ``k_r + s_max/2``, ``k_l - s_max/2`` and
    the target if it lies between those two.
    """
    n = len(masked)
    blocked = masked.nonzero()[0]
    if len(blocked) == n:
        return []
    if len(blocked) == 0:
        return [float(k_target) % n]
    start = int(blocked[0])  # rotate so that a blocked sector comes first
    # valleys: the gaps between consecutive blocked sectors of the rotated circle
    ends = [*(blocked - start).tolist(), n]
    out: list[float] = []
    for b0, b1 in itertools.pairwise(ends):
        width = b1 - b0 - 1
        if width <= 0:
            continue
        k_r = start + b0 + 1  # k_r .. k_r + width - 1 (unwrapped)
        k_l = k_r + width - 1
        if width <= s_max:
            out.append((k_r + (width - 1) / 2) % n)
        else:
            c_r, c_l = k_r + s_max / 2, k_l - s_max / 2
            out += [c_r % n, c_l % n]
            t = (k_target - k_r) % n + k_r  # the target unwrapped into this valley's frame
            if c_r <= t <= c_l:
                out.append(t % n)
    return out


def choose_direction(candidates: list[float], k_target: float, k_heading: float, k_prev: float,
                     n: int, mu: tuple[float, float, float]) -> float | None:
    """The candidate of least ``mu1 D(c, target) + mu2 D(c, heading) + mu3 D(c, previous)``
    (the first one on a tie)."""
    if not candidates:
        return None

    def dist(a: float, b: float) -> float:  # sector_distance in scalars
        d = abs(a - b) % n
        return min(d, n - d)

    costs = [mu[0] * dist(c, k_target) + mu[1] * dist(c, k_heading) + mu[2] * dist(c, k_prev)
             for c in candidates]
    return float(candidates[costs.index(min(costs))])


def roll_arc(length: float, sweep: float, steps: int = 8) -> np.ndarray:
    """(steps, 2) points along the path the centre rolls on when a turn on the spot is
    commanded at speed, in the body frame (x ahead, y left; m): ``length`` m of travel while
    the heading swings by ``sweep`` rad (+ left), the swing growing with the square of the
    travel (the turn rate ramps up under the wheels' acceleration limit while the centre keeps
    its speed; ``results/baselines/vfh_s18/``). The start (0, 0) is left out."""
    step = length / steps
    heading = sweep * ((np.arange(steps) + 0.5) / steps) ** 2  # mid-step headings
    return np.cumsum(np.stack([step * np.cos(heading), step * np.sin(heading)], axis=1), axis=0)


def spin_sign(v: float, omega: float) -> float:
    """The sign of a command's turn on the spot: +1 left, -1 right, 0 when it drives (``v``
    m/s not 0) or does not turn (``omega`` rad/s 0)."""
    return math.copysign(1.0, omega) if v == 0.0 and omega != 0.0 else 0.0


def relax_factors(relax_max: float) -> list[float]:
    """Threshold factors 2, 4, ... up to ``relax_max`` tried in turn when no valley is open."""
    return [2.0 ** i for i in range(1, int(math.log2(relax_max) + 1e-9) + 1)]


def near_sectors(cells_xy: np.ndarray, certainty: np.ndarray, xy: np.ndarray, n_sectors: int, r_rs: float,
                 reach: float, min_certainty: float) -> np.ndarray:
    """(n,) bool: sectors covered by the enlargement of a cell with certainty above
    ``min_certainty`` closer than ``reach`` m: a contact however the thresholds are set."""
    close = (np.hypot(*(cells_xy - xy).T) < reach) & (certainty > min_certainty) if len(cells_xy) else []
    if not np.any(close):
        return np.zeros(n_sectors, dtype=bool)
    return polar_histogram(cells_xy[close], np.ones(int(np.sum(close))), xy, n_sectors, r_rs, reach, 0.0) > 0


def select_direction(primary: np.ndarray, masked: np.ndarray, phi_r: float, phi_l: float, heading: float,
                     sectors: tuple[float, float, float], p: Any,
                     near: np.ndarray | None = None) -> tuple[float | None, np.ndarray, float]:
    """(chosen sector or None, the masked histogram it came from, threshold factor used).

    ``sectors`` = (target, heading, previous choice). First the valleys of ``masked`` (the
    hysteresis thresholds); if there are none, H^p is thresholded at ``f * threshold_high``
    for f = 2, 4, .. ``relax_max`` (same turning mask, and the sectors ``near`` (n,) bool of
    cells within reach stay blocked) until a valley opens. Why: with the
    shared grid a wall is marked certain (``c_max``) along its whole length, so a sector sums
    several wall cells; in a 1 m corridor walls 0.5..1.6 m away then close every sector and
    VFH+ would turn on the spot for ever although the robot fits (measured on the generated
    mazes; see the README). The relaxed valley is the least obstructed way out."""
    mu = (p.mu_goal, p.mu_heading, p.mu_previous)
    k_target, k_heading, k_prev = sectors
    n = len(primary)
    k = choose_direction(candidate_directions(masked, k_target, p.s_max), k_target, k_heading, k_prev, n, mu)
    if k is not None:
        return k, masked, 1.0
    for factor in relax_factors(p.relax_max):
        blocked = primary > factor * p.threshold_high
        relaxed = masked_histogram(blocked if near is None else blocked | near, heading, phi_r, phi_l)
        k = choose_direction(candidate_directions(relaxed, k_target, p.s_max), k_target, k_heading, k_prev, n, mu)
        if k is not None:
            return k, relaxed, factor
    return None, masked, 1.0


class VFHPlus(Planner):
    """VFH+ (Ulrich & Borenstein 1998) on the shared sonar occupancy grid read as certainty."""

    name: ClassVar[str] = "vfh_plus"
    reference: ClassVar[str] = ("Ulrich & Borenstein, VFH+: Reliable obstacle avoidance for fast "
                                "mobile robots, ICRA 1998")
    params: ClassVar[tuple[Param, ...]] = (
        Param("v_max", 0.4, "m/s", "top speed in free space (capped by the robot's limit)", minimum=0.0),
        Param("cell", 0.1, "m", "side of the occupancy grid's cells", minimum=0.01),
        Param("c_max", 15, "-", "certainty of a cell the grid holds certainly occupied (occupancy 100)",
              minimum=1),
        Param("window_radius", 1.2, "m", "radius of the active window around the robot", minimum=0.1),
        Param("sector_deg", 5.0, "deg", "angular width of a histogram sector", minimum=0.5, maximum=45.0),
        Param("safety_distance", 0.05, "m", "distance added to the robot radius to enlarge cells", minimum=0.0),
        Param("distance_weight", 7.11, "1/m^2", "b in m = c^2 (a - b d^2): how much nearer cells weigh",
              minimum=0.0),
        Param("threshold_low", 1500.0, "-", "histogram value below which a sector becomes free", minimum=0.0),
        Param("threshold_high", 2500.0, "-", "histogram value above which a sector becomes blocked",
              minimum=0.0),
        Param("mask_certainty", 3.0, "-", "cells above this certainty block the turning circles",
              minimum=0.0),
        Param("s_max", 16, "sectors", "valleys wider than this are wide (two border candidates)", minimum=1),
        Param("mu_goal", 5.0, "-", "cost weight of the difference to the goal direction", minimum=0.0),
        Param("mu_heading", 2.0, "-", "cost weight of the difference to the current heading", minimum=0.0),
        Param("mu_previous", 2.0, "-", "cost weight of the difference to the previous choice", minimum=0.0),
        Param("slow_density", 3000.0, "-", "histogram value in the heading at which the speed reaches zero",
              minimum=1e-6),
        Param("relax_max", 4.0, "-", "with no valley, threshold_high is doubled up to this factor until one "
              "opens (the robot then creeps at relaxed_speed); 1 turns it off", minimum=1.0),
        Param("relaxed_speed", 0.1, "m/s", "top speed while driving through a valley opened only by relax_max",
              minimum=0.0),
        Param("turn_in_place_deg", 60.0, "deg", "turn on the spot when the chosen direction is farther off",
              minimum=0.0, maximum=180.0),
        # the carving's settings: SeeThroughCarving's memory_s, undo, body_clear and body_memory_s
        Param("carve_seen_through", True, "-", "build the histogram from the parts of the grid's cells the "
              "sonars have not seen through from two views (nav_bench.planners.carving); false: whole cells"),
        Param("carve_memory_s", 10.0, "s", "how long a carved part stays carved (the two views that confirm it "
              "still within 3 s; D* Lite: 3)", minimum=0.0),
        Param("carve_undo", "unexplained", "-", "when an echo keeps carved parts again: off, axis (on a sonar's axis at "
              "the range read) or unexplained (on an echo's arc none of whose parts is kept); SeeThroughCarving "
              "undo", choices=UNDO_MODES),
        Param("carve_body_clear", 0.0, "m", "carve under the body only with no echo nearer (0: always)", minimum=0.0),
        Param("carve_body_memory_s", 10.0, "s", "how long the body's carving lasts (<= carve_memory_s)", minimum=0.0),
        # the brake before a turn on the spot and the cap on its rate: a spin commanded at speed
        # rolls the body on (results/baselines/vfh_s17/ to vfh_s20/)
        Param("roll_time_s", 0.6, "s", "a turn on the spot started at speed v rolls on about v times this "
              "(spin_probe: 18 cm from 0.3 m/s); the brake acts only where that roll meets a sure point, the "
              "cap on the turn rate (_capped) where it meets any window point", minimum=0.0),
        Param("roll_sweep_deg", 75.0, "deg", "how far the heading swings during that roll-on (the turn rate "
              "ramps up while the centre keeps its speed: 63-77 deg in 0.6 s in G6's traces); the brake tests the "
              "arc this bends the roll into, toward the turn (so does the cap)", minimum=0.0, maximum=180.0),
        Param("brake_speed", 0.02, "m/s", "a turn on the spot starts only below this speed; faster, the robot "
              "brakes straight first where the roll-on would meet a sure point (_spot_turn), and elsewhere a turn "
              "whose roll-on would meet a point is capped at 2 |v| / wheel base (_capped); 0: never brake",
              minimum=0.0),
    )

    def reset(self, obs: Observation, rng: np.random.Generator) -> None:
        super().reset(obs, rng)
        p = self.settings
        self.grid = OccupancyGrid(obs.bounds, cell=p.cell)
        self.frame = GridFrame.from_bounds(self.grid.bounds, self.grid.cell)
        self.carving = SeeThroughCarving(self.frame, obs.pose, memory_s=p.carve_memory_s,
                                         undo=p.carve_undo, body_clear=p.carve_body_clear,
                                         body_memory_s=p.carve_body_memory_s)
        if self.carving.compiled:
            _load_compiled_code()
        self.n = max(4, round(360.0 / p.sector_deg))
        self.alpha = 2 * math.pi / self.n
        self.binary = np.zeros(self.n, dtype=bool)
        self.k_prev = self._sector(float(obs.pose[2]))
        self.v_prev = 0.0
        self.turn_sign = 1.0
        self.blocked = False
        self.primary = np.zeros(self.n)
        self.masked = np.zeros(self.n, dtype=bool)
        self._speed = OdometrySpeed()  # m/s along the heading, from odometry (the brake's)
        self.spinning = 0.0  # the sign of the last command's turn on the spot (0: none, or a brake)

    def _sector(self, angle: float) -> float:
        return (angle % (2 * math.pi)) / self.alpha

    def act(self, obs: Observation) -> Command:
        p = self.settings
        robot = obs.robot
        self.grid.update(obs.pose, obs.ranges, obs.robot.sonar)
        xy, goal = np.asarray(obs.pose[:2], dtype=float), np.asarray(obs.goal, dtype=float)
        yaw = float(obs.pose[2])
        d_goal = float(np.hypot(*(goal - xy)))
        r_rs = robot.radius + p.safety_distance
        # obstacles beyond the goal cannot block the way to it: the window shrinks to the goal
        radius = min(p.window_radius, d_goal)
        window = (self._carved_window(obs, xy, radius) if p.carve_seen_through else
                  read_window(self.grid.values(copy=False), self.frame, xy, radius, p.c_max))
        bearings = window.bearings()
        self.primary = window_histogram(window, bearings, self.n, r_rs, p.window_radius, p.distance_weight)
        self.binary = binary_histogram(self.primary, self.binary, p.threshold_low, p.threshold_high)
        radius_turn = abs(self.v_prev) / robot.omega_max
        phi_r, phi_l = window_turning_limits(window, bearings, obs.pose, radius_turn, r_rs, p.mask_certainty)
        speed = self._speed(obs)
        self.masked = masked_histogram(self.binary, yaw, phi_r, phi_l)
        k_target = self._sector(math.atan2(goal[1] - xy[1], goal[0] - xy[0]))
        k_heading = self._sector(yaw)
        # relaxed thresholds must not open a sector toward a cell within r_rs + one cell
        near = (near_sectors(np.stack([window.x, window.y], axis=1), window.certainty, xy, self.n, r_rs,
                             r_rs + p.cell, p.mask_certainty)
                if self.masked.all() else None)
        k, self.masked, factor = select_direction(
            self.primary, self.masked, phi_r, phi_l, yaw, (k_target, k_heading, self.k_prev), p, near)
        v_top, slow = min(p.v_max, robot.v_max), p.slow_density
        if factor > 1.0:  # a valley opened only by relaxed thresholds: creep through it
            v_top, slow = min(v_top, p.relaxed_speed), factor * p.slow_density
        if k is None:  # no valley: stop and turn on the spot so the front sonars scan
            if not self.blocked:
                self.emit("blocked", obs.t)
            self.blocked, self.v_prev = True, 0.0
            omega = self._turn_on_the_spot(self.turn_sign * 0.5 * robot.omega_max, speed, window, yaw, robot)
            self.spinning = spin_sign(0.0, omega)
            return limit(0.0, omega, robot)
        self.blocked = False
        self.k_prev = k
        direction = k * self.alpha
        err = wrap_angle(direction - yaw)
        if abs(err) > 1e-9:
            self.turn_sign = math.copysign(1.0, err)
        omega = 2.5 * err
        if abs(err) > math.radians(p.turn_in_place_deg):
            v, omega = 0.0, self._turn_on_the_spot(omega, speed, window, yaw, robot)
        else:
            density = float(self.primary[round(k_heading) % self.n])
            v = v_top * (1.0 - min(density, slow) / slow)
            v = arrival_speed(d_goal, v) * max(0.0, math.cos(err))
        cmd = limit(v, omega, robot)
        self.v_prev = cmd.v
        self.spinning = spin_sign(v, omega)
        return cmd if math.isfinite(cmd.v) else STOP

    def _turn_on_the_spot(self, omega: float, speed: float, window: ActiveWindow, yaw: float,
                          robot: RobotInfo) -> float:
        """The turn rate, rad/s, of a turn on the spot asked at ``omega`` while the body moves at
        ``speed`` m/s: H3's brake (:meth:`_spot_turn`) decides first, then the cap on what is
        left (:meth:`_capped`); a braked turn (0) passes the cap unchanged."""
        return self._capped(self._spot_turn(omega, speed, window, yaw, robot.radius), speed, window, yaw, robot)

    def _spot_turn(self, omega: float, speed: float, window: ActiveWindow, yaw: float, radius: float) -> float:
        """The turn rate of a turn on the spot, rad/s: ``omega``, or 0 (brake straight) while the
        robot still moves faster than ``brake_speed`` m/s, has not begun this turn on the spot
        (the last command turned on the spot the same way), *and* the body rolling on would
        meet a sure point of ``window`` (certainty above ``mask_certainty``; ``radius`` m the
        body's, ``yaw`` rad the heading).

        Why: each wheel's acceleration is limited, so from speed v0 the centre keeps v0 until the
        outer wheel reaches its turning speed: the body rolls on 6 cm from 0.1 m/s and 18 cm from
        0.3 m/s (``results/baselines/vfh_s17/``). The roll bends toward the turn
        (:func:`roll_arc`: ``speed * roll_time_s`` m, the heading swinging ``roll_sweep_deg``),
        so the brake tests that arc, for points the body would come nearer. It brakes only
        before the turn begins: braked mid-turn, the inner wheel stops first and the outer one's
        speed carries the body on along the turned heading, into what the turn faced
        (``results/baselines/vfh_s18/``). A turn the other way is a new turn: the centre
        still rolls on, now bending the other way. Braking everywhere cost gap endings
        (``vfh_s17/lost_gap_endings.md``), so the brake is kept for rolls that would touch."""
        p = self.settings
        if self.spinning * omega > 0 or not (p.brake_speed > 0 and abs(speed) > p.brake_speed):
            return omega
        sure = window.certainty > p.mask_certainty
        return 0.0 if self._roll_meets(window, sure, omega, speed, yaw, radius) else omega

    def _roll_meets(self, window: ActiveWindow, points: np.ndarray | None, omega: float, speed: float, yaw: float,
                    radius: float) -> bool:
        """Whether the body rolling on from ``speed`` m/s into a turn on the spot the way of
        ``omega`` (:func:`roll_arc`: ``speed * roll_time_s`` m, the heading swinging
        ``roll_sweep_deg``) would come within ``radius`` m of one of the ``window``'s points
        selected by ``points`` (M,) bool (None: every point), and nearer than it is now (``yaw``
        rad the heading)."""
        dx, dy, dist = ((window.dx, window.dy, window.dist) if points is None else
                        (window.dx[points], window.dy[points], window.dist[points]))
        if len(dist) == 0:
            return False
        p = self.settings
        c, s_ = math.cos(yaw), math.sin(yaw)
        ahead, left = dx * c + dy * s_, -dx * s_ + dy * c  # body frame, m
        arc = roll_arc(abs(speed) * p.roll_time_s, math.copysign(math.radians(p.roll_sweep_deg), omega))
        nearest = np.hypot(ahead[:, None] - arc[None, :, 0], left[:, None] - arc[None, :, 1]).min(axis=1)
        meets = (nearest < radius) & (nearest < dist)
        return bool(meets.any())

    def _capped(self, omega: float, speed: float, window: ActiveWindow, yaw: float, robot: RobotInfo) -> float:
        """A turn on the spot while the body still rolls faster than ``brake_speed`` and its
        roll-on would meet a point of the ``window`` (any certainty: :meth:`_roll_meets`): at
        most the rate whose outer wheel speed is the present speed (2 |speed| / wheel base).

        Why: with v = 0 and a fast turn commanded, both wheels ramp at the same rate, the outer
        one up and the inner one down, so the centre keeps its speed until the outer wheel
        reaches the turn's speed (0.5 s for 5.8 rad/s from 0.25 m/s) and touches what lies on
        the roll (``results/baselines/vfh_s19/``); capped, only the inner wheel reverses and the
        centre slows from the start. Capped everywhere the robot touched 10 times less but lost
        the gaps it rolls into, so a roll into free space is left alone (gate: ``vfh_s20/``)."""
        if abs(speed) <= self.settings.brake_speed or abs(omega) <= 2.0 * abs(speed) / robot.wheel_base:
            return omega
        if not self._roll_meets(window, None, omega, speed, yaw, robot.radius):
            return omega
        return math.copysign(2.0 * abs(speed) / robot.wheel_base, omega)

    def _carved_window(self, obs: Observation, xy: np.ndarray, radius: float) -> ActiveWindow:
        """The active window (``radius`` m round ``xy``) with the parts of its cells the
        sonars have seen through carved away (:meth:`ActiveWindow.carved`)."""
        values = self.grid.values(copy=False)
        box = a0, a1, b0, b1 = window_box(self.frame, xy, radius)
        compiled = self.carving.compiled  # the window's kernels follow the carving's
        window = read_window(values, self.frame, xy, radius, self.settings.c_max, box, compiled)
        carved = self.carving.update(obs, window.rows, window.cols, box, values[a0:a1, b0:b1] > UNKNOWN)
        return window.carved(carved.kept, carved.parts, xy, compiled)

    def stuck_reason(self) -> StuckReason | None:
        """NO_PATH while no valley is open (every sector blocked: the robot turns on the spot
        to re-sense, which the episode would otherwise call pinned or oscillating)."""
        return StuckReason.NO_PATH if getattr(self, "blocked", False) else None

    def debug_state(self) -> dict[str, Any]:
        """The shared occupancy grid (:class:`~nav_bench.interface.GridState`: ``pmo``,
        ``bounds``, ``cell``), ``primary_histogram`` (n,), ``masked_histogram`` (n,) 0/1,
        ``direction_sector`` (sector 0 = world +x, CCW)."""
        if not hasattr(self, "grid"):
            return {}
        grids = GridState(pmo=self.grid.values(), bounds=self.grid.bounds, cell=self.grid.cell)
        return {**grids.state(), "primary_histogram": self.primary.copy(),
                "masked_histogram": self.masked.astype(np.uint8), "direction_sector": float(self.k_prev)}
