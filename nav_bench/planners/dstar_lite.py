"""D* Lite on an occupancy grid built from the sonars, with a pure-pursuit path follower.

Reference: S. Koenig and M. Likhachev, "D* Lite", Proceedings of the AAAI Conference on
Artificial Intelligence (AAAI-02), pp. 476-483, 2002 (the optimised version, Fig. 4, with
the basic version's full ``rhs`` recomputation for vertices whose edges changed).

The map: an :class:`~nav_bench.mapping.occupancy.OccupancyGrid` updated from the sonars
every cycle. Under the *freespace assumption* unknown cells are free; a cell whose value is
above ``occupied_above`` is an obstacle. Cell costs (:func:`clearance_costs`, ROS costmap
style, from the distances between cell centres, :func:`obstacle_distance`): obstacle cells
are lethal (``inf``); cells within ``radius + passage_margin`` of one (inscribed) cost
``inflated_cost`` per step, finite so that a robot whose surroundings a sonar arc painted over can still drive out; beyond that
the cost falls from ``clearance_cost`` to 1 at ``radius + passage_margin + inflation_margin``
as the 4th power of the margin left, so paths run down the middle of 1 m corridors and doors
and take a gap a few cm wider than the robot only when going round costs more. Distances come
from a Euclidean distance transform recomputed only in a window around the cells whose
occupancy flipped (and only the window the sonars can reach is compared each cycle). The
goal's cell is never lethal (an echo arc over the goal would otherwise make it unreachable for
good).

The graph: 8-connected cells; moving from ``u`` to a neighbour ``v`` costs the step length
(1 or sqrt 2 cells) times the cost of ``v``; a diagonal step is forbidden when either cell it
cuts past is lethal. The search runs backward from the goal, so ``g(s)`` is the cost from
``s`` to the goal and the robot descends it. Heuristic: octile distance (consistent).

The first plan (and a re-plan from scratch) is computed at once, not expanded cell by cell:
on the freespace assumption's uniform costs every cell's cost to the goal has a closed form
(:func:`uniform_costs_to_go`), otherwise SciPy's Dijkstra runs on the whole grid; both add
the same terms as the search, so every cell starts consistent (``g = rhs``) with nothing queued.

Incremental repair: when cells change, only the vertices whose outgoing edges changed (the
3 x 3 block around each changed cell) get ``rhs`` recomputed and are queued; ``km`` grows by
``h(s_last, s_start)`` when the robot has moved since the last change. ``g``/``rhs`` live in
flat Python lists (fast scalar access) over a grid padded with a one-cell lethal frame whose
``rhs`` is ``-inf`` (no bounds checks in the loops); the priority queue is a ``heapq`` with
lazy deletion (an entry counts while it is the vertex's current one). Keys are rounded to
2**-29 cells (one addition and one subtraction): ``g + h + km`` summed along different routes
must tie exactly, or a 1e-15 difference in ``k1`` overrides the ``k2`` tie-break and the
search stops one expansion early with a stale ``g``. The neighbour loops are written out
(:mod:`~nav_bench.planners.dstar_loops`).

The search's loops, in Python or compiled (``search_kernel``): :class:`CompiledSearch` runs
them as Numba kernels (:mod:`~nav_bench.planners.dstar_kernels`, the optional ``fast`` extra)
on NumPy arrays and an indexed binary heap, with the same results bit for bit; ``auto`` (the
default) uses it when Numba can be imported.

Time slicing (:class:`PathRepair`): at most ``expansions_per_cycle`` queue steps per control
cycle; an unfinished repair continues next cycle while the robot follows the part of its old
path that is still ahead and not inscribed/lethal (or stops). The path (a 160-cell prefix) is
extracted only when the repair settled after a change on it, and then only up to where it
meets the old path beyond the last cell next to a changed ``g`` or cost; moving along it
advances an offset. The map's changes are found in the sonars' window, their distances by a
patch of precomputed distances per new obstacle cell (a distance transform where one was freed).

The follower: pure pursuit on the path (``lookahead``), turning on the spot when the lookahead
point is more than ``turn_in_place_deg`` off the heading; in the goal's cell or next to it,
straight for the goal. Every command is checked by :func:`~nav_bench.planners.footprint.guard`:
the footprint's rollout over ``safety_horizon_s`` against the parts of the occupied cells near
the robot that the sonars have not seen through (each cell as 5 x 5 small squares, carved by
the readings of the last ``CARVE_MEMORY_S``: the grid stands up to a cell proud of surfaces
and narrows 0.55-0.6 m gaps below the robot's width) and against the sonar echoes; it keeps
``cruise_margin`` at ``v_max`` and ``squeeze_margin`` at ``squeeze_speed``, slows within
``slow_distance``, slides along a corner on another arc or turns to a heading it can leave it
by, and stops before it turns on the spot. No progress for ``recovery_after_s`` (odometry and
sonar evidence, a slow straight creep counting, :mod:`~nav_bench.planners.recovery`) starts
the recovery: back up (not into the map's obstacles), rotate in
place, re-plan from scratch (``recovery`` events with their ``phase``); no path starts a rotate
and, if there is still none, clears the map (at most ``no_path_recoveries`` times); after that:
stop and emit ``unreachable`` (once per loss). :meth:`DStarLite.stuck_reason` says why.

A repair after which the path ahead differs from the previous one emits a ``replan`` event.
:func:`astar` plans from scratch on the same graph (tests and ``benchmarks/bench_dstar.py``).
"""

from __future__ import annotations

import functools
import heapq
import math
from collections.abc import Iterable, Sequence
from types import ModuleType
from typing import Any, ClassVar

import numpy as np
from scipy import ndimage

from nav_bench import compiled
from nav_bench.errors import InputError
from nav_bench.interface import Command, GridState, Observation, StuckReason, wrap_angle
from nav_bench.mapping.occupancy import SONAR_MODELS, OccupancyGrid
from nav_bench.planners.base import Param, ParamError, Planner
from nav_bench.planners.carving import SeeThroughCarving
from nav_bench.planners.dstar_loops import _K, _Q, FULL, apply_costs, descend, recompute_rhs
from nav_bench.planners.follow import STOP, OdometrySpeed, arrival_speed, pure_pursuit, steer
from nav_bench.planners.footprint import (
    CARVE_SUB,
    Guarded,
    GuardSettings,
    PointObstacles,
    SquareClearance,
    guard,
)
from nav_bench.planners.recovery import ProgressWatch, Recovery, RecoveryPhase, RecoverySettings

INF = math.inf
SQRT2 = math.sqrt(2.0)
PATH_PREFIX = 160  # cells of the path extracted at a time (16..23 m; the follower looks 0.5 m ahead)
FLOOR_MARGIN = 0.01  # m: the least gap to the map's obstacles a robot inside its margin may dip to
ESCAPE_S = 4.0  # s: the longest the follower holds a way out of its margin
CLEARANCE_POWER = 4  # the clearance cost falls as this power of the fraction of the margin left
# (drow, dcol, step length in cells); fixed order makes tie-breaking deterministic
MOVES: tuple[tuple[int, int, float], ...] = (
    (0, 1, 1.0), (1, 0, 1.0), (0, -1, 1.0), (-1, 0, 1.0),
    (1, 1, SQRT2), (1, -1, SQRT2), (-1, -1, SQRT2), (-1, 1, SQRT2),
)


def disk(radius_cells: float) -> np.ndarray:
    """Boolean structuring element: offsets within ``radius_cells`` of the centre cell."""
    n = max(0, math.floor(radius_cells))
    dr, dc = np.mgrid[-n:n + 1, -n:n + 1]
    return np.hypot(dr, dc) <= radius_cells + 1e-9


def cell_costs(occupied: np.ndarray, inflate_cells: float, inflated_cost: float) -> np.ndarray:
    """(H, W) float step-cost multipliers: ``inf`` on occupied cells, ``inflated_cost`` within
    ``inflate_cells`` cells of one, 1 elsewhere."""
    occ = np.asarray(occupied, dtype=bool)
    near = ndimage.binary_dilation(occ, structure=disk(inflate_cells)) if occ.any() else occ
    cost = np.where(near, float(inflated_cost), 1.0)
    cost[occ] = INF
    return cost


def obstacle_distance(occupied: np.ndarray, cap: float) -> np.ndarray:
    """(H, W) distance, in cells, from each cell centre to the nearest occupied cell centre
    (0 on occupied cells), capped at ``cap`` (also where nothing is occupied)."""
    occ = np.asarray(occupied, dtype=bool)
    if not occ.any():
        return np.full(occ.shape, float(cap))
    return np.minimum(ndimage.distance_transform_edt(~occ), cap)


def clearance_costs(dist: np.ndarray, inscribed: float, margin: float, inscribed_cost: float,
                    clearance_cost: float) -> np.ndarray:
    """(H, W) step-cost multipliers from obstacle distances ``dist`` (cells, between cell
    centres: :func:`obstacle_distance`), ROS costmap style.

    ``inf`` on occupied cells (``dist == 0``); ``inscribed_cost`` within ``inscribed`` cells
    (the robot's radius and a little: the body would overlap an occupied cell however it stood
    in the cell); beyond it the cost falls from ``clearance_cost`` to
    1 at ``inscribed + margin`` cells as the fourth power of the remaining fraction
    (``CLEARANCE_POWER``), and is 1 farther out: steep near the obstacles, so that a gap a few
    cm wider than the robot costs as much as a detour of a few metres, nearly flat in the middle
    of a corridor. Costs are rounded to 1/64 so that equal distances give exactly equal costs.
    """
    d = np.asarray(dist, dtype=float)
    outer = inscribed + margin
    # (np.clip and np.round without their wrappers: the same values, a few us less per cycle)
    frac = np.minimum(np.maximum((outer - d) / max(margin, 1e-9), 0.0), 1.0)
    cost = np.rint((1.0 + (clearance_cost - 1.0) * frac ** CLEARANCE_POWER) * 64.0) / 64.0
    cost[d <= inscribed + 1e-9] = float(inscribed_cost)  # 1e-9: (0.18 + 0.02) / 0.1 < 2 in floats
    cost[d <= 0.0] = INF
    return cost




_FAR = 1 << 40  # a squared distance beyond any cap
_NO_ROWS = np.zeros(0, dtype=np.int64)  # no changes (read-only)
_NO_ROWS.flags.writeable = False
_NO_VALUES = np.zeros(0)
_NO_VALUES.flags.writeable = False

_COORDS: dict[tuple[int, int], tuple[list[int], list[int]]] = {}


def _coords(rows: int, width: int) -> tuple[list[int], list[int]]:
    """(row, column) of every flat index of a padded grid, as lists (shared: never written)."""
    key = (rows, width)
    if key not in _COORDS:
        flat = np.arange(rows * width)
        _COORDS.clear()  # one grid size at a time
        _COORDS[key] = ((flat // width).tolist(), (flat % width).tolist())
    return _COORDS[key]


def uniform_costs_to_go(rows: int, cols: int, goal: Sequence[int], cost: float = 1.0) -> np.ndarray:
    """(rows, cols) cost of the cheapest 8-connected path from each cell to ``goal`` when every
    cell costs ``cost`` (nothing lethal), summed as the search sums it.

    Mathematically ``cost`` times the octile distance; but the search's ``g`` is a float sum,
    ``g(s) = step * cost + g(next)``, and recomputing ``rhs`` must give ``g`` back bit for bit,
    or cells one ulp apart count as inconsistent. So the sums are built the same way, by
    Chebyshev ring (``a = max(|dr|, |dc|)``, ``b = min``): from ``(a, b)`` the steps on a
    cheapest path lead to ``(a - 1, b)`` (straight) or ``(a - 1, b - 1)`` (diagonal); every
    other neighbour is at least ``(2 - sqrt 2) cost`` dearer. One NumPy step per ring."""
    dr = np.abs(np.arange(rows) - int(goal[0]))[:, None]
    dc = np.abs(np.arange(cols) - int(goal[1]))[None, :]
    a, b = np.maximum(dr, dc), np.minimum(dr, dc)
    top = int(a.max())
    table = np.full((top + 1, top + 1), INF)  # table[a, b], b <= a
    table[0, 0] = 0.0
    straight, diagonal = 1.0 * cost, SQRT2 * cost
    for k in range(1, top + 1):
        prev, row = table[k - 1, :k], table[k]
        row[:k] = straight + prev
        np.minimum(row[1:k + 1], diagonal + prev, out=row[1:k + 1])
    return table[a, b]


def _queue_key(m: float, dr: int, dc: int, km: float) -> tuple[float, float]:
    """D* Lite's key (m + h + km, m) of a vertex with min(g, rhs) = ``m``, ``dr``, ``dc`` cells
    from the start (h: the octile distance), both rounded as the search's own loops round them
    (the hot loops, :meth:`DStarLiteSearch.compute` and :meth:`~DStarLiteSearch.set_costs`,
    write it out inline to save a call per vertex; this is its reference)."""
    dr, dc = (dr if dr > 0 else -dr), (dc if dc > 0 else -dc)
    return (m + (dr + dc + _K * (dr if dr < dc else dc)) + km + _Q) - _Q, (m + _Q) - _Q


class GridGraph:
    """An 8-connected grid with per-cell step costs, stored flat with a one-cell lethal frame.

    Cell ``(r, c)`` of the (H, W) grid is flat index ``(r + 1) * (W + 2) + (c + 1)``.
    :attr:`cost` is a Python list (fast scalar access in the search's loops); :attr:`cost_array`
    is the same costs as a NumPy array (vectorised change detection), kept equal by
    :meth:`DStarLiteSearch.set_costs`.
    """

    def __init__(self, cost: np.ndarray) -> None:
        cost = np.asarray(cost, dtype=float)
        if cost.ndim != 2 or np.any(cost < 1.0):
            raise InputError("cell costs must be an (H, W) array of values >= 1 (inf = lethal)")
        self.rows, self.cols = cost.shape
        self.width = w = self.cols + 2
        padded = np.full((self.rows + 2, w), INF)
        padded[1:-1, 1:-1] = cost
        self.cost_array = padded.ravel()
        self.cost: list[float] = self.cost_array.tolist()
        inner = np.zeros(padded.shape, dtype=bool)
        inner[1:-1, 1:-1] = True
        self.inner = bytearray(inner.ravel().tobytes())
        self.frame = np.flatnonzero(~inner.ravel())
        self.row, self.col = _coords(self.rows + 2, w)  # padded coordinates of each index
        # (flat offset, step, flat offsets of the two cells a diagonal cuts past or None)
        self.moves = [(dr * w + dc, step, (dr * w, dc) if dr and dc else None)
                      for dr, dc, step in MOVES]
        # flat offsets of a cell's 3 x 3 block
        self.block = np.array([dr * w + dc for dr in (-1, 0, 1) for dc in (-1, 0, 1)], dtype=np.int64)

    def index(self, rc: Sequence[int]) -> int:
        return (int(rc[0]) + 1) * self.width + int(rc[1]) + 1

    def flat(self, rows: Iterable[int], cols: Iterable[int]) -> np.ndarray:
        """(N,) int64 flat indices of the cells ``rows``, ``cols`` (:meth:`index` of each)."""
        return (np.asarray(rows, dtype=np.int64).reshape(-1) + 1) * self.width \
            + np.asarray(cols, dtype=np.int64).reshape(-1) + 1

    def cell(self, idx: int) -> tuple[int, int]:
        r, c = divmod(idx, self.width)
        return r - 1, c - 1

    def contains(self, rc: Sequence[int]) -> bool:
        return 0 <= rc[0] < self.rows and 0 <= rc[1] < self.cols

    def edge(self, u: int, off: int, step: float, cut: tuple[int, int] | None) -> float:
        """Cost of the step from ``u`` to ``u + off``."""
        cost = self.cost
        if cut is not None and (cost[u + cut[0]] == INF or cost[u + cut[1]] == INF):
            return INF
        return step * cost[u + off]

    def octile(self, a: int, b: int) -> float:
        ar, ac = divmod(a, self.width)
        br, bc = divmod(b, self.width)
        dr, dc = abs(ar - br), abs(ac - bc)
        return dr + dc + (SQRT2 - 2.0) * min(dr, dc)

    def reverse_csr(self) -> Any:
        """The graph with every edge reversed (``v -> s`` for each step ``s -> v``, weighted by
        that step's cost), as a sparse matrix over the flat indices: Dijkstra from the goal on it
        gives every cell's cost to the goal. Built with NumPy slices, one column per move."""
        from scipy.sparse import csr_matrix

        n, w = len(self.cost), self.width
        cost = self.cost_array
        ok = np.isfinite(cost)
        inner = np.frombuffer(self.inner, dtype=bool)
        lo, hi = w + 1, n - w - 1  # v over every inner cell (the frame has no edges)
        into = ok[lo:hi]  # no step enters a lethal cell
        straight, diagonal = cost[lo:hi], SQRT2 * cost[lo:hi]  # the search's own products
        targets = np.empty((hi - lo, len(MOVES)), dtype=np.int32)
        weights = np.empty((hi - lo, len(MOVES)))
        valid = np.empty((hi - lo, len(MOVES)), dtype=bool)
        vs = np.arange(lo, hi, dtype=np.int32)
        for j, (off, step, cut) in enumerate(self.moves):
            a, b = lo - off, hi - off  # s = v - off
            good = into & inner[a:b]
            if cut is not None:  # not past a lethal cell
                good &= ok[a + cut[0]:b + cut[0]] & ok[a + cut[1]:b + cut[1]]
            targets[:, j] = vs - off
            weights[:, j] = straight if step == 1.0 else diagonal
            valid[:, j] = good
        indptr = np.zeros(n + 1, dtype=np.int32)
        np.cumsum(valid.sum(axis=1), out=indptr[lo + 1:hi + 1])
        indptr[hi + 1:] = indptr[hi]
        return csr_matrix((weights[valid], targets[valid], indptr), shape=(n, n))


class DStarLiteSearch:
    """D* Lite (Koenig & Likhachev 2002) over a :class:`GridGraph`, searching from the goal.

    Args:
        cost: (H, W) step-cost multipliers (>= 1, ``inf`` lethal).
        start, goal: (row, col) cells.

    Call :meth:`compute` after construction, after :meth:`set_costs` and after
    :meth:`move_start`; :attr:`path_cost` is then the optimal cost (cells) from the start.
    :meth:`plan_from_scratch` instead of the first :meth:`compute` plans every cell at once (a
    closed form on uniform costs, else SciPy's Dijkstra) and leaves nothing queued.

    The loops are written out for speed (one expansion is ~20 list reads): ``rhs`` of the
    lethal frame's cells is ``-inf``, so that no test "lowers" or "went through" ever holds for
    them and the loops need no bounds check (the goal's ``rhs`` 0 is never above an edge's cost
    either); a queue entry is live while it is the one object ``entry[s]`` (lazy deletion).
    """

    def __init__(self, cost: np.ndarray, start: Sequence[int], goal: Sequence[int]) -> None:
        self.graph = GridGraph(cost)
        self._new_state(len(self.graph.cost))
        self.km = 0.0
        self.goal = self.graph.index(goal)
        self.start = self.graph.index(start)
        self.last = self.start
        self.expansions = 0
        self.touched: list[int] | None = None  # with a list, compute() appends each vertex whose g it sets
        self.steps = 0  # queue steps (expansions and re-keyings) over all compute() calls
        self.settled = False  # did the last compute() finish (not stopped by its budget)?
        self.rhs[self.goal] = 0.0
        self._update_vertex(self.goal)

    def _new_state(self, n: int) -> None:
        """``g`` and ``rhs`` (``-inf`` on the frame), the queue and the scratch marks of ``n``
        vertices, as Python lists (:class:`CompiledSearch`: arrays)."""
        self.g: list[float] = [INF] * n
        self.rhs: list[float] = [INF] * n
        for s in self.graph.frame.tolist():
            self.rhs[s] = -INF
        self.entry: list[tuple[float, float, int] | None] = [None] * n  # live queue entry or None
        self.heap: list[tuple[float, float, int]] = []
        self._scratch = bytearray(n)  # marks of set_costs and descend: all 0 between calls

    def _cells_and_costs(self, rows: Iterable[int], cols: Iterable[int],
                         values: Iterable[float]) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`set_costs`' cells as flat indices and their new costs, (N,) each."""
        flat = self.graph.flat(rows, cols)
        vals = np.asarray(values, dtype=float).reshape(-1)
        if len(flat) != len(vals):
            raise ValueError(f"{len(flat)} cells but {len(vals)} costs")
        return flat, vals

    # -- queue (lazy deletion) ---------------------------------------------------------------------
    def _update_vertex(self, u: int) -> None:
        """Queue ``u`` with its key if it is inconsistent, else drop its entry."""
        g, rhs = self.g[u], self.rhs[u]
        if g == rhs:
            self.entry[u] = None
            return
        m = g if g < rhs else rhs
        row, col, start = self.graph.row, self.graph.col, self.start
        dr, dc = row[u] - row[start], col[u] - col[start]
        dr, dc = (dr if dr > 0 else -dr), (dc if dc > 0 else -dc)
        self.entry[u] = e = ((m + (dr + dc + _K * (dr if dr < dc else dc)) + self.km + _Q) - _Q,
                             (m + _Q) - _Q, u)
        heapq.heappush(self.heap, e)

    def _recompute_rhs(self, s: int) -> float:
        """min over the successors ``v`` of c(s, v) + g(v)
        (:func:`~nav_bench.planners.dstar_loops.recompute_rhs`)."""
        return recompute_rhs(self.graph.cost, self.g, self.graph.width, s)

    # -- the algorithm -----------------------------------------------------------------------------
    def compute(self, max_expansions: int | None = None) -> int:
        """ComputeShortestPath; returns the number of expansions it made. With
        ``max_expansions`` it stops after that many queue steps (expansions and re-keyings)
        and :attr:`settled` stays False: call it again to continue."""
        g, rhs, entry, heap, graph = self.g, self.rhs, self.entry, self.heap, self.graph
        cost, row, col, w = graph.cost, graph.row, graph.col, graph.width
        start, km = self.start, self.km
        sr, sc = row[start], col[start]
        pop, push, replace = heapq.heappop, heapq.heappush, heapq.heapreplace
        recompute, update = recompute_rhs, self._update_vertex  # (a plain call: 3.11 inlines it)
        touched = self.touched if self.touched is not None else []
        budget = -1 if max_expansions is None else max_expansions

        def lower(s: int, val: float) -> None:
            """rhs(s) falls to val (rhs -inf of the frame and 0 of the goal never do)."""
            rhs[s] = val
            gs = g[s]
            if gs == val:
                entry[s] = None
                return
            m = gs if gs < val else val
            dr, dc = row[s] - sr, col[s] - sc
            dr, dc = (dr if dr > 0 else -dr), (dc if dc > 0 else -dc)
            entry[s] = e = ((m + (dr + dc + _K * (dr if dr < dc else dc)) + km + _Q) - _Q, (m + _Q) - _Q, s)
            push(heap, e)

        done = steps = 0
        self.settled = False
        while True:
            gs, rs = g[start], rhs[start]
            ms = gs if gs < rs else rs
            ks1 = ks2 = INF
            if ms != INF:
                ks1, ks2 = (ms + km + _Q) - _Q, (ms + _Q) - _Q
            while heap:  # the top live entry
                top = heap[0]
                if entry[top[2]] is top:
                    break
                pop(heap)
            else:
                self.settled = True
                break
            k1, k2, u = top
            if not (k1 < ks1 or (k1 == ks1 and k2 < ks2) or rs > gs):
                self.settled = True
                break
            if steps == budget:
                break
            steps += 1  # re-keying a vertex counts toward the budget as well: it costs as much
            gu, ru = g[u], rhs[u]
            mu = gu if gu < ru else ru
            dr, dc = row[u] - sr, col[u] - sc
            dr, dc = (dr if dr > 0 else -dr), (dc if dc > 0 else -dc)
            n1 = (mu + (dr + dc + _K * (dr if dr < dc else dc)) + km + _Q) - _Q
            n2 = (mu + _Q) - _Q
            if k1 < n1 or (k1 == n1 and k2 < n2):
                entry[u] = e = (n1, n2, u)
                replace(heap, e)
                continue
            pop(heap)
            entry[u] = None
            done += 1
            touched.append(u)
            cu = cost[u]
            if gu > ru:  # overconsistent: settle, and lower the predecessors it is now cheaper through
                g[u] = ru
                if cu == INF:
                    continue  # no step enters a lethal cell
                val = cu + ru  # a straight step into u, then on from u (written out: the hot loop)
                if val < rhs[u - 1]:
                    lower(u - 1, val)
                if val < rhs[u - w]:
                    lower(u - w, val)
                if val < rhs[u + 1]:
                    lower(u + 1, val)
                if val < rhs[u + w]:
                    lower(u + w, val)
                val = SQRT2 * cu + ru  # a diagonal step: not past a lethal cell
                if cost[u - 1] != INF:
                    if cost[u - w] != INF and val < rhs[u - w - 1]:
                        lower(u - w - 1, val)
                    if cost[u + w] != INF and val < rhs[u + w - 1]:
                        lower(u + w - 1, val)
                if cost[u + 1] != INF:
                    if cost[u - w] != INF and val < rhs[u - w + 1]:
                        lower(u - w + 1, val)
                    if cost[u + w] != INF and val < rhs[u + w + 1]:
                        lower(u + w + 1, val)
            else:  # underconsistent: raise to inf, repair u and the predecessors that used it
                g[u] = INF
                if cu != INF:
                    left, right = cost[u - 1] != INF, cost[u + 1] != INF
                    down, up = cost[u - w] != INF, cost[u + w] != INF
                    val = cu + gu - 1e-9  # s may have taken its rhs through u
                    for s in (u - 1, u - w, u + 1, u + w):
                        if rhs[s] >= val:
                            rhs[s] = recompute(cost, g, w, s)
                            update(s)
                    val = SQRT2 * cu + gu - 1e-9
                    for s in ((u - w - 1) if left and down else 0, (u - w + 1) if right and down else 0,
                              (u + w + 1) if right and up else 0, (u + w - 1) if left and up else 0):
                        if rhs[s] >= val:
                            rhs[s] = recompute(cost, g, w, s)
                            update(s)
                update(u)  # rhs(u) does not depend on g(u): it is still exact
        self.expansions += done
        self.steps += steps
        return done

    def plan_from_scratch(self) -> None:
        """Plan on the current costs at C/NumPy speed instead of the first :meth:`compute`:
        every cell's cost to the goal, ``g = rhs`` everywhere, nothing queued (the state a
        finished search leaves, for every cell instead of those the heuristic let it reach).

        With all costs equal (the freespace assumption's first plan) :func:`uniform_costs_to_go`,
        else SciPy's Dijkstra on the reversed graph (:meth:`GridGraph.reverse_csr`). Both add
        the search's own terms (``g(v) + step * cost(v)``, one addition per step), so ``rhs``
        recomputed from the result equals it bit for bit: every cell is consistent."""
        g, rhs = self._costs_to_go()
        self.g = g.tolist()
        self.rhs = rhs.tolist()
        self.entry = [None] * len(self.g)
        self.heap = []
        self.settled = True

    def _costs_to_go(self) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`plan_from_scratch`'s ``g`` and ``rhs`` as flat arrays: every inner cell's cost
        to the goal (``inf`` on the frame; ``rhs`` the same but ``-inf`` on the frame and 0 at
        the goal)."""
        graph = self.graph
        inner = np.frombuffer(graph.inner, dtype=np.uint8) == 1
        costs = graph.cost_array[inner]
        if len(costs) and np.isfinite(costs[0]) and np.all(costs == costs[0]):
            field = uniform_costs_to_go(graph.rows, graph.cols, graph.cell(self.goal), float(costs[0]))
            dist = np.full(len(graph.cost), INF)
            dist.reshape(graph.rows + 2, graph.width)[1:-1, 1:-1] = field
        else:
            from scipy.sparse.csgraph import dijkstra  # (imported on first use: ~0.1 s)

            dist = dijkstra(graph.reverse_csr(), directed=True, indices=self.goal)
            dist[~inner] = INF
        rhs = dist.copy()
        rhs[~inner] = -INF
        rhs[self.goal] = 0.0
        return dist, rhs

    def move_start(self, rc: Sequence[int]) -> None:
        """The robot is now in cell ``rc`` (call :meth:`compute` afterwards).

        ``km`` grows at once (the paper grows it at the next cost change): a search
        interrupted by its budget continues with a moved start, and the queued keys must
        stay lower bounds of the keys computed from the new start."""
        new = self.graph.index(rc)
        if new != self.start:
            self.km += self.graph.octile(self.last, new)
            self.last = new
        self.start = new

    def set_costs(self, rows: Iterable[int], cols: Iterable[int], values: Iterable[float]) -> int:
        """Change cell costs and update the vertices whose outgoing edges changed. Returns the
        number of cells that really changed.

        The paper's optimised update (Fig. 4, :func:`~nav_bench.planners.dstar_loops.apply_costs`):
        an edge into ``v`` that got cheaper lowers the predecessor's ``rhs`` by one comparison;
        one that got dearer recomputes it only if the predecessor's ``rhs`` went through ``v``.
        A cell that becomes or stops being lethal also changes the diagonal edges cutting past
        it: its whole 3 x 3 block is recomputed. (A cell given twice ends with its last value,
        as if they were set one by one.)"""
        graph = self.graph
        w, cost, g, rhs, inner, mark = graph.width, graph.cost, self.g, self.rhs, graph.inner, self._scratch
        flat, vals = self._cells_and_costs(rows, cols, values)
        changed, marked = apply_costs(flat.tolist(), vals.tolist(), cost, g, rhs, w, mark)
        if not changed:
            return 0
        if self.touched is not None:
            self.touched.extend(changed)
        graph.cost_array[changed] = [cost[v] for v in changed]
        self.km += graph.octile(self.last, self.start)
        self.last = self.start
        mark[self.goal] = 0  # the goal's rhs stays 0 and it is not queued
        recompute = recompute_rhs
        for u in marked:
            if mark[u] & FULL and inner[u]:
                rhs[u] = recompute(cost, g, w, u)
        # queue the inconsistent ones (the order of pushes does not matter: keys are unique)
        entry, heap, push, km, row, col = self.entry, self.heap, heapq.heappush, self.km, graph.row, graph.col
        sr, sc = row[self.start], col[self.start]
        for u in marked:
            if not mark[u]:
                continue
            mark[u] = 0
            gu, ru = g[u], rhs[u]
            if gu == ru or not inner[u]:
                entry[u] = None
                continue
            m = gu if gu < ru else ru  # _queue_key, written out (up to a hundred a cycle)
            dr, dc = row[u] - sr, col[u] - sc
            dr, dc = (dr if dr > 0 else -dr), (dc if dc > 0 else -dc)
            entry[u] = e = ((m + (dr + dc + _K * (dr if dr < dc else dc)) + km + _Q) - _Q, (m + _Q) - _Q, u)
            push(heap, e)
        return len(changed)

    @property
    def path_cost(self) -> float:
        """Cost (cells) of the shortest path from the start to the goal; inf if none."""
        return self.rhs[self.start] if self.start != self.goal else 0.0

    def queued(self) -> list[tuple[float, float, int]]:
        """The queue's live entries ``(k1, k2, vertex)``, least first (for tests and tools)."""
        return sorted(e for e in self.entry if e is not None)

    def path(self, max_len: int | None = None, join: dict[tuple[int, int], int] | None = None,
             tail: list[tuple[int, int]] | None = None) -> list[tuple[int, int]]:
        """Cells from the start to the goal by descending ``c + g``; [] if there is no path.

        With ``join`` (cell -> index in ``tail``, a path extracted on the same costs), the
        descent stops at the first cell of ``tail`` it meets and continues with ``tail`` from
        there (the descent from that cell would be the same)."""
        cell = self.graph.cell
        flat = self.descend(max_len)
        out = [cell(s) for s in flat]
        if join is not None and tail is not None:
            for i in range(1, len(out)):
                if out[i] in join:
                    return out[:i + 1] + tail[join[out[i]] + 1:]
        return out

    def descend(self, max_len: int | None = None, index: np.ndarray | None = None,
                after: int = -1) -> list[int]:
        """Flat indices from the start to the goal (at most ``max_len``) by descending
        ``c + g``, the first of equal successors in :data:`MOVES`' order; [] if there is none
        (:func:`~nav_bench.planners.dstar_loops.descend`). With ``index`` (flat index -> index
        in a path, -1 off it), it stops at the first cell after the start that ``index`` maps
        above ``after``."""
        if self.path_cost == INF:
            return []
        return descend(self.graph.cost, self.g, self.graph.width, self.start, self.goal,
                       max_len or len(self.g), _NO_ROWS if index is None else index, after, self._scratch)

SEARCH_KERNELS = compiled.kernel_choices("python")  # choices of DStarLite's search_kernel


def load_kernels() -> ModuleType | None:
    """:mod:`nav_bench.planners.dstar_kernels`, or None when Numba cannot be imported
    (:func:`nav_bench.compiled.load`)."""
    return compiled.load("nav_bench.planners.dstar_kernels")


def make_search(cost: np.ndarray, start: Sequence[int], goal: Sequence[int],
                kernel: str = "python") -> DStarLiteSearch:
    """A D* Lite search with the loops of ``kernel``: ``python`` (:class:`DStarLiteSearch`),
    ``numba`` (:class:`CompiledSearch`; an :class:`~nav_bench.errors.InputError` without
    Numba) or ``auto`` (numba when it can be imported, else python). Both give the same
    ``g``, ``rhs``, expansions and paths, bit for bit."""
    if not compiled.use_kernels(kernel, load_kernels, "search", reference="python"):
        return DStarLiteSearch(cost, start, goal)
    search = CompiledSearch(cost, start, goal)
    _load_compiled_code()
    return search


@functools.cache
def _load_compiled_code() -> None:
    """Call every kernel once, on a 3 x 3 grid, so that Numba loads their machine code from its
    cache (or compiles it) now, while the planner is set up, once per process: left to the
    first call, it made the first control cycle last ~1 s."""
    search = CompiledSearch(np.ones((3, 3)), (0, 0), (2, 2))
    search.plan_from_scratch()
    search.set_costs([1], [1], [2.0])
    search.compute()
    search.descend()
    search._recompute_rhs(search.graph.index((1, 1)))


class CompiledSearch(DStarLiteSearch):
    """:class:`DStarLiteSearch` with :meth:`compute`, :meth:`set_costs`' loop and
    :meth:`descend` run by the Numba kernels of :mod:`nav_bench.planners.dstar_kernels` (the
    same operations in the same order: the same results, bit for bit).

    The state lives in NumPy arrays the kernels update in place: :attr:`g`, :attr:`rhs` and
    ``graph.cost`` (which is ``graph.cost_array``) are float arrays instead of lists, and the
    queue is an indexed binary heap (``_heap``, ``_pos``, ``_k1``, ``_k2``, ``_size``) instead
    of ``heap``/``entry``: :meth:`queued` lists it. Without Numba: an
    :class:`~nav_bench.errors.InputError`.
    """

    def __init__(self, cost: np.ndarray, start: Sequence[int], goal: Sequence[int]) -> None:
        if load_kernels() is None:
            raise InputError("search_kernel 'numba' needs Numba: pip install 'nav-bench[fast]'")
        super().__init__(cost, start, goal)

    def _new_state(self, n: int) -> None:
        graph = self.graph
        graph.cost = graph.cost_array  # type: ignore[assignment]  # one array both sides read
        self.g = np.full(n, INF)  # type: ignore[assignment]
        self.rhs = np.full(n, INF)  # type: ignore[assignment]
        self.rhs[graph.frame] = -INF
        self._inner = np.frombuffer(graph.inner, dtype=np.uint8)
        self._heap = np.zeros(n, dtype=np.int64)  # heap[:size[0]]: the queued vertices
        self._pos = np.full(n, -1, dtype=np.int64)  # each vertex's place in the heap (-1: none)
        self._k1, self._k2 = np.zeros(n), np.zeros(n)  # each queued vertex's key
        self._size = np.zeros(1, dtype=np.int64)
        self._scratch = np.zeros(n, dtype=np.int8)  # the kernels' marks, all 0 between calls
        self._no_join = np.zeros(0, dtype=np.int64)  # descend without a path to join

    @property
    def _kernels(self) -> ModuleType:
        """:mod:`nav_bench.planners.dstar_kernels` (looked up, not kept: a search pickles)."""
        return load_kernels()  # type: ignore[return-value]

    def _queue(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        return self._heap, self._pos, self._k1, self._k2, self._size

    def _update_vertex(self, u: int) -> None:
        self._kernels.update_vertex(self.g, self.rhs, *self._queue(), u, self.start,
                                    self.graph.width, self.km)

    def _recompute_rhs(self, s: int) -> float:
        return float(self._kernels.recompute_rhs(self.graph.cost_array, self.g, self.graph.width, s))

    def compute(self, max_expansions: int | None = None) -> int:
        budget = -1 if max_expansions is None else int(max_expansions)
        done, steps, settled, touched = self._kernels.compute(
            self.g, self.rhs, self.graph.cost_array, *self._queue(), self.start, self.graph.width,
            self.km, budget)
        self.settled = bool(settled)
        if self.touched is not None:
            self.touched.extend(touched.tolist())
        self.expansions += done
        self.steps += steps
        return int(done)

    def plan_from_scratch(self) -> None:
        self.g, self.rhs = self._costs_to_go()  # type: ignore[assignment]
        self._pos[:] = -1
        self._size[0] = 0
        self.settled = True

    def set_costs(self, rows: Iterable[int], cols: Iterable[int], values: Iterable[float]) -> int:
        graph = self.graph
        w = graph.width
        flat, vals = (np.ascontiguousarray(a) for a in self._cells_and_costs(rows, cols, values))
        km = self.km + graph.octile(self.last, self.start)  # km's growth, if anything changes
        changed = self._kernels.set_costs(flat, vals, graph.cost_array, self.g, self.rhs, self._inner,
                                          *self._queue(), self._scratch, w, self.goal, self.start, km)
        if not changed:
            return 0
        if self.touched is not None:
            self.touched.extend(changed)
        self.km, self.last = km, self.start
        return len(changed)

    @property
    def path_cost(self) -> float:
        return float(self.rhs[self.start]) if self.start != self.goal else 0.0

    def queued(self) -> list[tuple[float, float, int]]:
        heap = self._heap[:self._size[0]].tolist()
        return sorted((float(self._k1[u]), float(self._k2[u]), u) for u in heap)

    def descend(self, max_len: int | None = None, index: np.ndarray | None = None,
                after: int = -1) -> list[int]:
        if self.path_cost == INF:
            return []
        graph = self.graph
        return self._kernels.descend(graph.cost_array, self.g, graph.width, self.start, self.goal,
                                     max_len or len(self.g), self._no_join if index is None else index,
                                     after, self._scratch)


def astar(cost: np.ndarray, start: Sequence[int], goal: Sequence[int]
          ) -> tuple[float, list[tuple[int, int]]]:
    """A* from scratch on the same graph as :class:`DStarLiteSearch` (octile heuristic).

    Returns (cost in cells, path as (row, col) from start to goal); (inf, []) if unreachable.
    """
    graph = GridGraph(cost)
    gcost, moves, inner = graph.cost, graph.moves, graph.inner
    s0, goal_i = graph.index(start), graph.index(goal)
    g: dict[int, float] = {s0: 0.0}
    parent: dict[int, int] = {}
    closed: set[int] = set()
    heap = [(graph.octile(s0, goal_i), 0.0, s0)]
    while heap:
        _, gu, u = heapq.heappop(heap)
        if u in closed:
            continue
        if u == goal_i:
            path = [u]
            while path[-1] != s0:
                path.append(parent[path[-1]])
            return gu, [graph.cell(i) for i in reversed(path)]
        closed.add(u)
        for off, step, cut in moves:
            v = u + off
            if not inner[v] or v in closed:
                continue
            if cut is not None and (gcost[u + cut[0]] == INF or gcost[u + cut[1]] == INF):
                continue
            c = step * gcost[v]
            if c == INF:
                continue
            gv = gu + c
            if gv < g.get(v, INF):
                g[v] = gv
                parent[v] = u
                heapq.heappush(heap, (gv + graph.octile(v, goal_i), gv, v))
    return INF, []


class PathRepair:
    """D* Lite with a budget of expansions per control cycle, keeping its path between cycles.

    Each :meth:`cycle` moves the start, applies the cost changes and runs at most ``budget``
    expansions (0: unlimited); an interrupted search continues next cycle. While it is
    unfinished, :attr:`cells` is the part of the last complete path that is still ahead of
    the robot and not lethal (at most ``keep`` cells), or [] (stop). The path is extracted
    only when the search has settled after a cost change on it (or the robot left the path);
    a robot moving along its path only advances an offset into it (no O(path) work). With
    ``prefix`` > 0 only that many cells are extracted (a follower needs the near part), and
    the next piece when the robot has used half of them.

    A new path is spliced, not extracted anew: the search lists the vertices whose ``g``
    changed (:attr:`DStarLiteSearch.touched`) and the cells whose cost changed; the old
    path's steps after the last one next to such a cell are still the descent, so the new
    path descends from the robot only until it meets the old one beyond that point. With
    ``scratch`` (the default) the first plan and every :meth:`restart` are
    :meth:`DStarLiteSearch.plan_from_scratch`. ``kernel`` chooses the search's loops
    (:func:`make_search`: python, numba or auto).
    """

    def __init__(self, cost: np.ndarray, start: Sequence[int], goal: Sequence[int],
                 budget: int = 0, keep: int = 30, lethal: float = INF, prefix: int = 0,
                 scratch: bool = True, kernel: str = "python") -> None:
        self.budget, self.keep, self.lethal, self.prefix = budget, keep, lethal, prefix
        self.scratch, self.kernel = scratch, kernel
        self.version = 0  # counts path extractions
        self._new_search(cost, start, goal)
        self.cycle(tuple(start))

    def _new_search(self, cost: np.ndarray, start: Sequence[int], goal: Sequence[int]) -> None:
        self.search = make_search(cost, start, goal, self.kernel)
        if self.scratch:
            self.search.plan_from_scratch()
        self.search.touched = []
        self._path: list[tuple[int, int]] = []
        self._flat: list[int] = []  # the path's flat indices
        self._where: dict[int, int] = {}  # flat index -> index in the path
        self._offset = 0
        self._near = -1  # a path index beside the robot while it is off its path
        self.stale = True  # the path no longer reflects the costs (a repair is under way)
        self._costs_changed = True  # on the path since the last extraction (else it may still do)
        self._extend = True  # the next extraction descends from scratch (no splice)
        self._g_path: list[float] = []  # g of each path cell at extraction (the start's: its rhs)
        self._index = np.full(len(self.search.g), -1, dtype=np.int64)  # flat index -> path index

    @property
    def complete(self) -> bool:
        """Has the search settled on the current costs and start?"""
        return self.search.settled

    @property
    def offset(self) -> int:
        """Index in :attr:`full_path` of the robot's cell."""
        return self._offset

    @property
    def full_path(self) -> list[tuple[int, int]]:
        """The last extracted path (its first cell is where the robot was then)."""
        return self._path

    @property
    def cells(self) -> list[tuple[int, int]]:
        """The path from the robot's cell to the goal ([] if there is none, or while a repair is
        unfinished and the old path is lethal or left behind)."""
        start, stop = self.span
        return self._path[start:stop]

    @property
    def span(self) -> tuple[int, int]:
        """:attr:`cells` as the slice ``[start:stop]`` of :attr:`full_path` (a follower that
        keeps the full path's points slices them instead of converting the cells anew)."""
        if not self.stale:
            return self._offset, len(self._path)
        return self._safe_prefix()

    def _nearby(self, rc: tuple[int, int], last: int) -> int:
        """Index of a cell of the path within 2 cells of ``rc`` near the last offset, or -1
        (pure pursuit cuts corners: the robot is often beside its path, not on it)."""
        if last < 0:
            return -1
        for i in range(max(last - 5, 0), min(last + 40, len(self._path))):
            r, c = self._path[i]
            if abs(r - rc[0]) <= 2 and abs(c - rc[1]) <= 2:
                return i
        return -1

    def _safe_prefix(self) -> tuple[int, int]:
        """The slice of the path ahead of the robot up to its first lethal cell (at most
        ``keep`` cells; (0, 0): none)."""
        start = self._offset if self._offset >= 0 else self._near
        if not self._path or start < 0:
            return 0, 0
        cost, lethal = self.search.graph.cost, self.lethal
        flat = self._flat[start:start + self.keep]
        for i in range(1, len(flat)):
            if cost[flat[i]] >= lethal:
                return (start, start + i) if i > 1 else (0, 0)
        return start, min(start + self.keep, len(self._path))

    def cycle(self, start: Sequence[int], rows: np.ndarray | None = None,
              cols: np.ndarray | None = None, vals: np.ndarray | None = None) -> tuple[int, bool]:
        """One control cycle. Returns (cells whose cost changed, whether a new path was extracted
        after a cost change made the old one differ)."""
        search = self.search
        start = (int(start[0]), int(start[1]))
        s = search.graph.index(start)
        moved = s != search.start
        search.move_start(start)
        changed = search.set_costs(rows, cols, vals) if rows is not None and len(rows) else 0
        if changed:
            self.stale = True
            if self._costs_changed or self._hits_path(rows, cols, vals):
                self._costs_changed = True
        if moved:
            last = self._offset if self._offset >= 0 else self._near
            self._offset = self._where.get(s, -1)
            if self._offset < 0:
                self.stale = True  # left the path: its suffix is no answer
                self._near = self._nearby(start, last)
            elif (self.prefix and len(self._path) - self._offset < self.prefix // 2
                  and self._flat[-1] != search.goal):
                self.stale = self._costs_changed = self._extend = True  # extract the next piece
        if self.stale or not search.settled:
            search.compute(self.budget or None)
        if not (self.stale and search.settled):
            return changed, False
        old = self._path[max(self._offset, 0):]
        if (not self._costs_changed and self._offset >= 0
                and abs(search.path_cost - self._g_path[self._offset]) < 1e-9):
            # no cost on the path changed and the cost from here did not: still optimal
            self.stale = False
            return changed, False
        self._extract()
        return changed, bool(changed) and bool(self._path) and _path_changed(old, self._path)

    def _extract(self) -> None:
        """The path from the start: a descent of at most ``prefix`` cells, joined to the old path
        where the old one is still the descent (at once if only the robot left its path)."""
        search = self.search
        graph, touched, where = search.graph, search.touched, self._where
        after = -1  # the last old step that may have changed
        if self._extend or not self._flat or len(touched) > 20000:  # (then descending is cheaper)
            flat = search.descend(self.prefix or None)
        else:
            if touched:  # an old step next to a changed g or cost may have changed
                near = np.unique(np.asarray(touched, dtype=np.int64))
                near = (near[:, None] + graph.block[None, :]).ravel()
                after = int(self._index[near].max())
            flat = search.descend(self.prefix or None, index=self._index, after=after)
        self._index[self._flat] = -1
        g, w = search.g, graph.width
        cells = [(v // w - 1, v % w - 1) for v in flat]
        g_new = [search.path_cost] + [g[v] for v in flat[1:]]
        j = where.get(flat[-1], -1) if flat and after >= -1 and not self._extend else -1
        if j > after:  # joined: the old path from there on
            flat = flat + self._flat[j + 1:]
            cells += self._path[j + 1:]
            g_new += self._g_path[j + 1:]
        self._flat, self._path, self._g_path = flat, cells, g_new
        self._where = {v: i for i, v in enumerate(flat)}
        self._index[flat] = np.arange(len(flat))
        touched.clear()
        self._costs_changed = self._extend = False
        self.version += 1
        self._offset = 0
        self.stale = False

    def _hits_path(self, rows: np.ndarray, cols: np.ndarray, vals: np.ndarray) -> bool:
        """Did a cost on the path ahead change, or did a cell next to it become lethal (a
        diagonal step may cut past it)? (Looked up in :attr:`_index`, the path index of each
        flat index, for all the changed cells at once.)"""
        if not self._where:
            return False
        start, block = max(self._offset, 0), self.search.graph.block
        flat = (np.asarray(rows, dtype=np.int64) + 1) * self.search.graph.width + np.asarray(cols) + 1
        if (self._index[flat] >= start).any():
            return True
        lethal = flat[np.asarray(vals) == INF]
        return bool(len(lethal)) and bool((self._index[(lethal[:, None] + block[None, :]).ravel()] >= start).any())

    def restart(self, cost: np.ndarray, start: Sequence[int]) -> None:
        """Plan anew from scratch on ``cost`` (a forced re-plan)."""
        self._new_search(cost, start, self.search.graph.cell(self.search.goal))
        self.cycle(tuple(start))


class DStarLite(Planner):
    """D* Lite (Koenig & Likhachev 2002) on a sonar occupancy grid, freespace assumption, with a
    clearance cost, a footprint-checking pure-pursuit follower and a back-up/rotate recovery."""

    name: ClassVar[str] = "dstar_lite"
    reference: ClassVar[str] = "Koenig & Likhachev, D* Lite, AAAI 2002"
    params: ClassVar[tuple[Param, ...]] = (
        Param("v_max", 0.4, "m/s", "cruise speed (capped by the robot's limit)", minimum=0.0),
        Param("cell", 0.1, "m", "side of the occupancy grid's cells", minimum=0.01),
        Param("occupied_above", 65, "0..100", "occupancy value above which a cell is an obstacle",
              minimum=50, maximum=99),
        Param("sonar_model", "elfes", "-", "the grid's inverse sensor model (nav_bench.mapping.occupancy): "
              "'elfes' weighs by angle and shares the echo over its arc; 'band' the whole arc (before issue 12)",
              choices=SONAR_MODELS),
        Param("inflation_margin", 0.35, "m",
              "clearance beyond the inscribed one over which the cell cost falls to 1", minimum=0.0),
        # finite, not lethal: a sonar arc drawn over the robot's own surroundings must not cut
        # it off; 1000 makes the planner use such cells only when nothing else is free
        Param("inflated_cost", 1000.0, "-", "step-cost factor of inscribed cells (within radius + "
              "passage_margin of an occupied cell)", minimum=1.0),
        Param("clearance_cost", 5.0, "-", "step-cost factor just beyond the inscribed clearance, falling "
              "as the 4th power to 1 at radius + passage_margin + inflation_margin", minimum=1.0),
        Param("expansions_per_cycle", 250, "-", "D* Lite expansions per control cycle; an unfinished "
              "repair continues next cycle (0: unlimited)", minimum=0),
        # the same rows either way (tests/planners/test_dstar_kernels.py); numba: ~3x less CPU per repair
        Param("search_kernel", "auto", "-", "the search's loops: 'numba' compiled (the optional 'fast' "
              "extra), 'python', or 'auto' (numba when it can be imported); the results are the same",
              choices=SEARCH_KERNELS, neutral=True),
        Param("lookahead", 0.5, "m", "pure-pursuit lookahead distance along the path", minimum=0.05),
        Param("turn_in_place_deg", 60.0, "deg", "turn on the spot when the path is farther off the heading",
              minimum=0.0, maximum=180.0),
        Param("safety_horizon_s", 1.0, "s", "the commanded motion's footprint is checked against the "
              "map this far ahead", minimum=0.1),
        Param("slow_distance", 0.1, "m", "slow down when the clearance ahead is less than this beyond "
              "the required one", minimum=0.0),
        Param("squeeze_margin", 0.02, "m", "gap the follower keeps between the body and an occupied "
              "cell (the square it covers) at squeeze speed", minimum=0.0),
        Param("cruise_margin", 0.06, "m", "the same gap at cruise speed (v_max); it grows linearly "
              "from squeeze_speed", minimum=0.0),
        Param("squeeze_speed", 0.1, "m/s", "speed at which only squeeze_margin is kept; the follower "
              "slides along a corner at this speed when the path's own curvature is not safe",
              minimum=0.01),
        Param("passage_margin", 0.02, "m", "a cell is inscribed (inflated_cost) within the robot radius "
              "plus this of an occupied cell, centre to centre", minimum=0.0),
        Param("recovery_after_s", 6.0, "s", "start the recovery (back up, rotate, re-plan) after this "
              "long without progress (0: never)", minimum=0.0),
        Param("progress_m", 0.3, "m", "displacement or gain toward the goal that counts as progress",
              minimum=0.05),
        Param("backup_m", 0.25, "m", "how far the recovery backs up", minimum=0.0),
        Param("rotate_deg", 360.0, "deg", "how far the recovery turns in place to re-sense", minimum=0.0),
        # sonar arcs can close a real gap for good; forgetting the map (freespace assumption)
        # lets the robot look again, a bounded number of times so an unreachable goal still ends
        Param("no_path_recoveries", 3, "-", "recoveries per episode when there is no path: rotate to "
              "re-sense, then clear the map if there is still none", minimum=0),
    )

    @classmethod
    def check_rules(cls, p: dict[str, Any]) -> None:
        # 'numba' asks for what this installation may not have: say so before anything is
        # simulated (in a reset it would end every episode as an error)
        if p["search_kernel"] == "numba" and load_kernels() is None:
            raise ParamError("search_kernel 'numba' needs Numba, which is not installed (or does not "
                             "support this NumPy): pip install 'nav-bench[fast]', or use 'auto'",
                             "search_kernel")

    def reset(self, obs: Observation, rng: np.random.Generator) -> None:
        super().reset(obs, rng)
        self.reset_path(obs)
        p = self.settings
        x0, y0, _x1, _y1 = self.grid.bounds
        # the follower's exact clearance to the map's occupied squares (reads self.occupied)
        self._squares = SquareClearance(self.occupied, x0, y0, p.cell, self._clearance_cap(obs))
        v = min(p.v_max, obs.robot.v_max)
        self.guard_settings = GuardSettings(
            required=obs.robot.radius + p.squeeze_margin, horizon=p.safety_horizon_s,
            slow_distance=p.slow_distance, cruise_extra=max(0.0, p.cruise_margin - p.squeeze_margin),
            squeeze_speed=min(p.squeeze_speed, v), v_max=v, floor=obs.robot.radius + FLOOR_MARGIN)
        rs = RecoverySettings(after_s=p.recovery_after_s, progress_m=p.progress_m, backup_m=p.backup_m,
                              rotate_rad=math.radians(p.rotate_deg),
                              omega=min(1.0, 0.6 * obs.robot.omega_max))
        self.watch = ProgressWatch(rs)
        self.watch.restart(obs)
        self.recovery = Recovery(rs)
        self.blocked = False  # the follower found no safe motion this cycle
        self.last_reason: StuckReason | None = None
        self.no_path_left = p.no_path_recoveries
        self._carving = SeeThroughCarving(self.grid.frame, obs.pose)  # parts of cells seen through
        self._odometry_speed = OdometrySpeed()
        self._speed = 0.0
        self._escape: tuple[float, float] | None = None  # (world heading, since when) of a way out
        self._near = self._squares

    def required_clearance(self, obs: Observation) -> float:
        """The distance (m, cell centre to the nearest occupied cell's centre) within which the
        search treats a cell as inscribed: the robot radius plus ``passage_margin``."""
        return obs.robot.radius + self.settings.passage_margin

    def reset_path(self, obs: Observation) -> None:
        """The grid, the obstacle distances and costs, and the first D* Lite plan (what
        ``dwa_global`` shares)."""
        p = self.settings
        self.grid = OccupancyGrid(obs.bounds, cell=p.cell, model=p.sonar_model)
        self.shape = self.grid.shape
        # inscribed cells: within the robot radius plus passage_margin of an occupied cell,
        # centre to centre (2 cells with the defaults: a gap of four free cells or fewer is
        # inscribed, of five is not, however the grid's cells fall on it). The follower's
        # guard measures exactly, to the parts of the cells the sonars have not seen through:
        # the grid narrows 0.55-0.6 m gaps to four free cells or five, and the robot passes them.
        self.inscribed = self.required_clearance(obs) / p.cell
        self.margin_cells = p.inflation_margin / p.cell
        self.cap = self.inscribed + self.margin_cells + 1.0  # distances beyond change no cost
        self.pad = math.ceil(self.cap)
        # the sonars change cells only this far from the robot
        self.window = math.ceil((obs.robot.sonar.max_range + 2 * p.cell) / p.cell) + 1
        self.occupied = np.zeros(self.shape, dtype=bool)
        self.dist = np.full(self.shape, self.cap)  # cells: clearance of each cell's best point
        self.cost = np.ones(self.shape)
        self.goal_rc = self._clamp(self.grid.world_to_cell(obs.goal))
        self.goal_xy = np.asarray(obs.goal, dtype=float)
        start = self._clamp(self.grid.world_to_cell(obs.pose[:2]))
        self.repair = PathRepair(self.cost, start, self.goal_rc, budget=p.expansions_per_cycle,
                                 lethal=p.inflated_cost, prefix=PATH_PREFIX, kernel=p.search_kernel)
        self._path_id = -1
        self._xy_full = np.zeros((0, 2))
        self._refresh_xy()
        self.unreachable = False

    @property
    def search(self) -> DStarLiteSearch:
        return self.repair.search

    @property
    def cells(self) -> list[tuple[int, int]]:
        """The path from the robot's cell to the goal (what it follows now)."""
        return self.repair.cells

    def _cell_of(self, xy: np.ndarray) -> tuple[int, int]:
        """(row, col) of the grid cell holding the point ``xy[:2]`` (m)
        (:meth:`~nav_bench.mapping.grid.GridFrame.cell_of`)."""
        return self.grid.frame.cell_of(float(xy[0]), float(xy[1]))

    def _clamp(self, rc: Sequence[int]) -> tuple[int, int]:
        h, w = self.shape
        return (int(min(max(rc[0], 0), h - 1)), int(min(max(rc[1], 0), w - 1)))

    def _to_world(self, cells: list[tuple[int, int]]) -> np.ndarray:
        if not cells:
            return np.zeros((0, 2))
        rc = np.array(cells)
        xy = self.grid.cell_center(rc[:, 0], rc[:, 1])
        if cells[-1] == self.goal_rc:
            xy[-1] = self.goal_xy  # end at the goal itself, not its cell centre
        return xy

    def _refresh_xy(self) -> None:
        """Recompute the world path only when a new one was extracted."""
        if self.repair.version != self._path_id:
            self._path_id = self.repair.version
            self._xy_full = self._to_world(self.repair.full_path)
        start, stop = self.repair.span  # (the points of the cells: cell_center is elementwise)
        self.path_xy = self._xy_full[start:stop]

    def _clearance_cap(self, obs: Observation) -> float:
        """Clearances beyond this (m) change nothing the follower does."""
        p = self.settings
        return obs.robot.radius + max(p.cruise_margin, p.passage_margin) + p.slow_distance + p.cell

    def clearance(self, xy: np.ndarray) -> np.ndarray:
        """(N,) m from points ``xy`` (N, 2) to the nearest occupied cell, each taken as the square
        it covers (exact geometry; capped a cell beyond what the follower needs; 0 outside the
        grid)."""
        if self._squares.occupied is not self.occupied:  # the map array was replaced
            self._squares.occupied = self.occupied
        return self._squares(xy)

    def _local_clearance(self, obs: Observation) -> PointObstacles:
        """The clearance the follower and the recovery check motions against this cycle: exact
        distances to the parts of the occupied cells near the robot that the sonars have not
        seen through (nor the body covered) in the last ``CARVE_MEMORY_S``
        (:class:`~nav_bench.planners.carving.SeeThroughCarving`: each cell is checked as
        ``CARVE_SUB`` x ``CARVE_SUB`` small squares, one counts as seen through from two views).
        The grid blames a whole echo arc and a cell needs many readings to be carved free
        again, so it stands up to a cell proud of obstacles and narrows a 0.58 m gap to
        ~0.4 m, too narrow for the body; the readings themselves tell which parts of those
        cells the sonars see through."""
        cell = self.settings.cell
        cap = self._squares.cap
        pose = np.asarray(obs.pose, dtype=float)
        reach = min(self.settings.v_max, obs.robot.v_max) * self.settings.safety_horizon_s + cap + 0.2
        n = math.ceil(reach / cell)
        r0, c0 = self._cell_of(pose)
        h, w = self.shape
        a0, a1, b0, b1 = max(r0 - n, 0), min(r0 + n + 1, h), max(c0 - n, 0), min(c0 + n + 1, w)
        a1, b1 = max(a1, a0), max(b1, b0)  # an empty box when the robot is far outside the grid
        window = self.occupied[a0:a1, b0:b1]
        rr, cc = np.nonzero(window)
        carved = self._carving.update(obs, rr + a0, cc + b0, (a0, a1, b0, b1), window)
        return PointObstacles(carved.kept_parts(), cell / (2 * CARVE_SUB), cap, self.grid.bounds,
                              compiled=self._carving.compiled)

    def _map_changes(self, robot_rc: tuple[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Cells whose cost changed since the last cycle (rows, cols, new costs).

        Only the window the sonars can reach around the robot is compared; distances and costs
        are recomputed only around the cells whose occupancy flipped. When cells only became
        occupied (the usual case), distances can only shrink, to the new cells: each new cell
        lowers its disc of radius ``cap`` to a precomputed patch of distances (the same values
        a distance transform gives); a freed cell raises the distances of the cells it was
        nearest to (:meth:`_lift_freed`). Costs are recomputed for the cells whose distance
        changed."""
        h, w = self.shape
        n = self.window
        a0, a1 = max(robot_rc[0] - n, 0), min(robot_rc[0] + n + 1, h)
        b0, b1 = max(robot_rc[1] - n, 0), min(robot_rc[1] + n + 1, w)
        occ = self.grid.values(copy=False)[a0:a1, b0:b1] > self.settings.occupied_above
        gr, gc = self.goal_rc[0] - a0, self.goal_rc[1] - b0
        if 0 <= gr < a1 - a0 and 0 <= gc < b1 - b0:
            occ[gr, gc] = False  # the goal cell is never lethal
        known = self.occupied[a0:a1, b0:b1]
        flipped = occ != known
        if not flipped.any():
            return _NO_ROWS, _NO_ROWS, _NO_VALUES
        fr, fc = np.nonzero(flipped)
        freed = known[fr, fc]
        known[fr, fc] = ~freed
        fr += a0
        fc += b0
        m = self.pad
        # the box round the flips, from Python ints (a few flips a cycle: four NumPy
        # reductions cost more than min and max of short lists)
        rows, cols = fr.tolist(), fc.tolist()
        r0, r1 = max(min(rows) - m, 0), min(max(rows) + m + 1, h)
        c0, c1 = max(min(cols) - m, 0), min(max(cols) + m + 1, w)
        dist = self.dist[r0:r1, c0:c1]  # distances can change only within cap (m cells) of a flip
        before = dist.copy()
        if freed.any():
            self._lift_freed(dist, r0, c0, fr[freed], fc[freed])
        patch = self._patch()
        for r, c in zip((fr[~freed] - r0).tolist(), (fc[~freed] - c0).tolist(), strict=True):
            # a new obstacle lowers its disc to the patch's distances (centre on (r, c), cut to the box)
            pr0, pc0 = max(m - r, 0), max(m - c, 0)
            br0, bc0 = max(r - m, 0), max(c - m, 0)
            br1, bc1 = min(r + m + 1, r1 - r0), min(c + m + 1, c1 - c0)
            sub = dist[br0:br1, bc0:bc1]
            np.minimum(sub, patch[pr0:pr0 + br1 - br0, pc0:pc0 + bc1 - bc0], out=sub)
        # a cell's cost is a function of its distance alone: only cells whose distance changed
        # can change cost (in row-major order, as a comparison of the whole box lists them)
        dr, dc = np.nonzero(dist != before)
        p = self.settings
        vals = clearance_costs(dist[dr, dc], self.inscribed, self.margin_cells, p.inflated_cost,
                               p.clearance_cost)
        old = self.cost[r0:r1, c0:c1]
        moved = vals != old[dr, dc]
        dr, dc, vals = dr[moved], dc[moved], vals[moved]
        old[dr, dc] = vals
        return dr + r0, dc + c0, vals

    def _lift_freed(self, dist: np.ndarray, r0: int, c0: int, fr: np.ndarray, fc: np.ndarray) -> None:
        """Raise, in ``dist`` (the box of :attr:`dist` from row ``r0``, column ``c0``), the
        distances of the cells whose nearest obstacle may have been one of the freed cells
        ``fr``, ``fc`` (grid rows and columns, already free in :attr:`occupied`): the cells as
        near to a freed cell as to their nearest obstacle. Each is measured again to every
        occupied cell within ``cap`` (cell centres, ``sqrt(dr^2 + dc^2)`` as the distance
        transform gives it); the others keep theirs, which no freed cell set."""
        h, w = self.shape
        m = self.pad
        rows = np.arange(r0, r0 + dist.shape[0])
        cols = np.arange(c0, c0 + dist.shape[1])
        d2 = np.full(dist.shape, _FAR)
        for r, c in zip(fr.tolist(), fc.tolist(), strict=True):
            np.minimum(d2, (rows[:, None] - r) ** 2 + (cols[None, :] - c) ** 2, out=d2)
        # a freed cell nearer than the recorded distance cannot be: the two are equal where the
        # cell was nearest (sqrt is correctly rounded, so equal squares give equal distances)
        ar, ac = np.nonzero((np.sqrt(d2.astype(float)) <= dist) & (dist < self.cap))
        if len(ar) == 0:
            return
        R0, C0 = max(r0 - m, 0), max(c0 - m, 0)
        R1, C1 = min(r0 + dist.shape[0] + m, h), min(c0 + dist.shape[1] + m, w)
        orow, ocol = np.nonzero(self.occupied[R0:R1, C0:C1])
        drow = (ar + (r0 - R0))[:, None] - orow[None, :]
        dcol = (ac + (c0 - C0))[:, None] - ocol[None, :]
        near2 = (drow * drow + dcol * dcol).min(axis=1, initial=_FAR)
        dist[ar, ac] = np.minimum(np.sqrt(near2.astype(float)), self.cap)

    def _patch(self) -> np.ndarray:
        """(2 pad + 1, 2 pad + 1) distances from the centre cell, capped at ``cap`` (cached)."""
        m = self.pad
        if getattr(self, "_patch_key", None) != (m, self.cap):
            dr, dc = np.mgrid[-m:m + 1, -m:m + 1]
            self._patch_cache = np.minimum(np.sqrt((dr * dr + dc * dc).astype(float)), self.cap)
            self._patch_key = (m, self.cap)
        return self._patch_cache

    def update_path(self, obs: Observation) -> bool:
        """Fuse the sonars into the grid, repair the search (within its budget) and refresh
        :attr:`path_xy`; emits ``replan`` when the path ahead changed and ``unreachable`` (once per
        loss) when there is none. Returns whether there is a path to follow now (False also
        while an unfinished repair leaves nothing safe of the old path). ``dwa_global`` follows
        the same path with DWA."""
        self.grid.update(obs.pose, obs.ranges, obs.robot.sonar)
        start = self._clamp(self._cell_of(obs.pose))
        rows, cols, vals = self._map_changes(start)
        changed, replanned = self.repair.cycle(start, rows, cols, vals)
        self._refresh_xy()
        if replanned:
            self.emit("replan", obs.t, changed_cells=int(changed),
                      cost_m=float(self.search.path_cost * self.settings.cell))
        if len(self.path_xy) == 0:
            if self.repair.complete and not self.unreachable:
                self.emit("unreachable", obs.t)
                self.unreachable = True
            return False
        self.unreachable = False
        return True

    def act(self, obs: Observation) -> Command:
        has_path = self.update_path(obs)
        self.watch.update(obs)
        self._speed = self._odometry_speed(obs)
        self._near = self._local_clearance(obs)
        p = self.settings
        if self.recovery.active:
            phase = self.recovery.phase
            cmd = self.recovery.step(obs, self._near, self.guard_settings.required)
            if cmd is not None:
                if self.recovery.phase is not phase:
                    self.emit("recovery", obs.t, phase=str(self.recovery.phase), count=self.recovery.count)
                return cmd
            self._replan(obs)
            has_path = len(self.path_xy) > 0
        elif p.recovery_after_s > 0 and (
                (not self.unreachable and self.watch.stalled_for(obs.t) >= p.recovery_after_s)
                or (self.unreachable and self.no_path_left > 0)):
            if self.unreachable:
                self.no_path_left -= 1
                self.last_reason = StuckReason.NO_PATH
            else:
                self.last_reason = self.watch.reason() or (StuckReason.STOPPED if self.blocked else None)
            self.recovery.start(obs, backup=not self.unreachable)
            self.emit("recovery", obs.t, phase=str(self.recovery.phase), count=self.recovery.count,
                      reason=str(self.last_reason) if self.last_reason else "no_progress")
            cmd = self.recovery.step(obs, self._near, self.guard_settings.required)
            if cmd is not None:
                return cmd
        if not has_path:
            return STOP
        guarded = self._follow(obs)
        self.blocked = guarded.blocked and guarded.command.v == 0.0
        return guarded.command

    def _replan(self, obs: Observation) -> None:
        """End of a recovery: plan from scratch on the re-sensed map, count progress anew."""
        start = self._clamp(self.grid.world_to_cell(obs.pose[:2]))
        self.repair.restart(self.cost, start)
        self.repair.search.compute()  # a recovery has stopped the robot: no budget for this one
        self.repair.cycle(start)
        if not self.repair.cells and self.last_reason is StuckReason.NO_PATH:
            self.emit("recovery", obs.t, phase=str(RecoveryPhase.CLEAR_MAP), count=self.recovery.count)
            self._clear_map(start)
        self._refresh_xy()
        self.unreachable = False
        self.watch.restart(obs)
        self.emit("recovery", obs.t, phase=str(RecoveryPhase.REPLAN), count=self.recovery.count,
                  path=bool(len(self.path_xy)))

    def _clear_map(self, start: tuple[int, int]) -> None:
        """Forget the map (every cell unknown, so free) and plan anew."""
        self.grid.reset()
        self.occupied[:] = False
        self.dist[:] = self.cap
        self.cost[:] = 1.0
        self.repair.restart(self.cost, start)
        self.repair.search.compute()
        self.repair.cycle(start)

    def _follow(self, obs: Observation) -> Guarded:
        """Pure pursuit on the path (straight for the goal in its cell or next to it), checked
        by :func:`~nav_bench.planners.footprint.guard` against the obstacle distances."""
        p = self.settings
        xy, goal = np.asarray(obs.pose[:2], dtype=float), self.goal_xy
        v = min(p.v_max, obs.robot.v_max)
        path = self.path_xy[:64]  # pure pursuit looks 0.5 m ahead: the near part is enough
        if len(self.path_xy) <= 2 and self.path_xy is not None and self.repair.complete:
            d = float(np.hypot(*(goal - xy)))
            toward = math.atan2(goal[1] - xy[1], goal[0] - xy[0])
            wanted = steer(obs, toward, arrival_speed(d, v))
            target = goal
        else:
            d = np.hypot(path[:, 0] - xy[0], path[:, 1] - xy[1])
            far = np.nonzero(d >= p.lookahead)[0]
            target = path[far[0]] if len(far) else path[-1]
            toward = math.atan2(target[1] - xy[1], target[0] - xy[0])
            wanted = pure_pursuit(obs, path, p.lookahead, v, turn_in_place=math.radians(p.turn_in_place_deg))
        if self._escape is not None:  # hold a way out of the margin until out (or it closes)
            heading, since = self._escape
            inside = float(self._near(xy[None, :])[0]) < self.guard_settings.required
            if inside and obs.t - since < ESCAPE_S:
                ahead = xy + np.array([math.cos(heading), math.sin(heading)])
                out = guard(obs, steer(obs, heading, self.guard_settings.squeeze_speed,
                                       turn_in_place=math.radians(15.0)),
                            heading, self._near, self.guard_settings, target=ahead, speed=self._speed)
                if out.command.v > 0.0 or abs(wrap_angle(heading - float(obs.pose[2]))) > math.radians(15.0):
                    return out
            self._escape = None
        out = guard(obs, wanted, toward, self._near, self.guard_settings, target=target, speed=self._speed)
        if out.escape is not None:
            self._escape = (out.escape, obs.t)
        return out

    def stuck_reason(self) -> StuckReason | None:
        """NO_PATH when the goal is unreachable on the map; PINNED or OSCILLATING when the
        progress watch saw it (now or when the last recovery started); WAITING while an
        unfinished repair holds the robot; STOPPED when the follower found no safe motion."""
        if getattr(self, "unreachable", False):
            return StuckReason.NO_PATH
        if not hasattr(self, "watch"):
            return None
        reason = self.watch.reason() or self.last_reason
        if reason is not None:
            return reason
        if not self.repair.complete and len(self.path_xy) == 0:
            return StuckReason.WAITING
        return StuckReason.STOPPED if self.blocked else None

    def debug_state(self) -> dict[str, Any]:
        """The occupancy grid (:class:`~nav_bench.interface.GridState`, so plots draw it),
        ``cost`` (H, W) step-cost factors (inf lethal), ``path`` (N, 2) m, and ``search_kernel``,
        the loops that ran (``numba`` or ``python``: ``auto`` resolved; the trace keeps it, as an
        episode's CPU time depends on it)."""
        if not hasattr(self, "grid"):
            return {}
        grids = GridState(pmo=self.grid.values(), bounds=self.grid.bounds, cell=self.grid.cell)
        kernel = "numba" if isinstance(self.repair.search, CompiledSearch) else "python"
        return {**grids.state(), "cost": self.cost.copy(), "path": self.path_xy.copy(),
                "search_kernel": kernel}


def _path_changed(old: list[tuple[int, int]], new: list[tuple[int, int]]) -> bool:
    """Does ``new`` leave the route of ``old``? Equal once ``new`` joins ``old``, from there on,
    means only the robot's own position moved (not a re-plan)."""
    if not old:
        return True
    where = {c: i for i, c in enumerate(old)}
    for j, cell in enumerate(new):
        if cell in where:
            i = where[cell]
            n = min(len(new) - j, len(old) - i)  # both may be prefixes of their paths
            return new[j:j + n] != old[i:i + n]
    return True
