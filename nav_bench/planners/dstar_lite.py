"""D* Lite on an occupancy grid built from the sonars, with a pure-pursuit path follower.

Reference: S. Koenig and M. Likhachev, "D* Lite", Proceedings of the AAAI Conference on
Artificial Intelligence (AAAI-02), pp. 476-483, 2002 (the optimised version, Fig. 4, with
the basic version's full ``rhs`` recomputation for vertices whose edges changed).

The map: an :class:`~nav_bench.mapping.occupancy.OccupancyGrid` updated from the sonars
every cycle. Under the *freespace assumption* unknown cells are free; a cell whose value is
above ``occupied_above`` is an obstacle. Cell costs (:func:`cell_costs`): obstacle cells
are lethal (``inf``); cells within ``radius + inflation_margin`` of an obstacle cost
``inflated_cost`` per step instead of 1, so paths keep their distance when they can, yet a
robot whose own cell was inflated (sonar arcs make obstacles look wider than they are)
can still drive out. The goal's cell is never lethal (an echo arc over the goal would
otherwise make it unreachable for good).

The graph: 8-connected cells; moving from ``u`` to a neighbour ``v`` costs the step length
(1 or sqrt 2 cells) times the cost of ``v``; a diagonal step is forbidden when either cell it
cuts past is lethal. The search runs backward from the goal, so ``g(s)`` is the cost from
``s`` to the goal and the robot descends it. Heuristic: octile distance (consistent).

Incremental repair: when cells change, only the vertices whose outgoing edges changed (the
3 x 3 block around each changed cell) get ``rhs`` recomputed and are queued; ``km`` grows by
``h(s_last, s_start)`` when the robot has moved since the last change. ``g``/``rhs`` live in
flat Python lists (fast scalar access) over a grid padded with a one-cell lethal frame; the
priority queue is a ``heapq`` with lazy deletion (an entry counts only while it matches the
vertex's current key). Keys are rounded to 1e-9 cells: ``g + h + km`` summed along
different routes must tie exactly, or a 1e-15 difference in ``k1`` overrides the ``k2``
tie-break and the search stops one expansion early with a stale ``g``.

The follower: pure pursuit on the cell path (``lookahead``), turning on the spot when the
lookahead point is more than ``turn_in_place_deg`` off the heading; in the goal's cell or
next to it, straight for the goal. No path -> stop and emit ``unreachable`` (once per loss).

A repair after which the path ahead differs from the previous one emits a ``replan`` event.
:func:`astar` plans from scratch on the same graph (tests and ``benchmarks/bench_dstar.py``).
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Iterable, Sequence
from typing import Any, ClassVar

import numpy as np
from scipy import ndimage

from nav_bench.errors import InputError
from nav_bench.interface import Command, GridState, Observation
from nav_bench.mapping.occupancy import SONAR_MODELS, OccupancyGrid
from nav_bench.planners.base import Param, Planner
from nav_bench.planners.follow import STOP, arrival_speed, pure_pursuit, steer

INF = math.inf
SQRT2 = math.sqrt(2.0)
KEY_DIGITS = 9  # keys are rounded so that sums equal up to float rounding tie exactly
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


class GridGraph:
    """An 8-connected grid with per-cell step costs, stored flat with a one-cell lethal frame.

    Cell ``(r, c)`` of the (H, W) grid is flat index ``(r + 1) * (W + 2) + (c + 1)``.
    """

    def __init__(self, cost: np.ndarray) -> None:
        cost = np.asarray(cost, dtype=float)
        if cost.ndim != 2 or np.any(cost < 1.0):
            raise InputError("cell costs must be an (H, W) array of values >= 1 (inf = lethal)")
        self.rows, self.cols = cost.shape
        self.width = self.cols + 2
        padded = np.full((self.rows + 2, self.width), INF)
        padded[1:-1, 1:-1] = cost
        self.cost: list[float] = padded.ravel().tolist()
        inner = np.zeros(padded.shape, dtype=bool)
        inner[1:-1, 1:-1] = True
        self.inner = bytearray(inner.ravel().tobytes())
        w = self.width
        # (flat offset, step, flat offsets of the two cells a diagonal cuts past or None)
        self.moves = [(dr * w + dc, step, (dr * w, dc) if dr and dc else None)
                      for dr, dc, step in MOVES]

    def index(self, rc: Sequence[int]) -> int:
        return (int(rc[0]) + 1) * self.width + int(rc[1]) + 1

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


class DStarLiteSearch:
    """D* Lite (Koenig & Likhachev 2002) over a :class:`GridGraph`, searching from the goal.

    Args:
        cost: (H, W) step-cost multipliers (>= 1, ``inf`` lethal).
        start, goal: (row, col) cells.

    Call :meth:`compute` after construction, after :meth:`set_costs` and after
    :meth:`move_start`; :attr:`path_cost` is then the optimal cost (cells) from the start.
    """

    def __init__(self, cost: np.ndarray, start: Sequence[int], goal: Sequence[int]) -> None:
        self.graph = GridGraph(cost)
        n = len(self.graph.cost)
        self.g: list[float] = [INF] * n
        self.rhs: list[float] = [INF] * n
        self.key: list[tuple[float, float] | None] = [None] * n  # queued key, None = not queued
        self.heap: list[tuple[float, float, int]] = []
        self.km = 0.0
        self.goal = self.graph.index(goal)
        self.start = self.graph.index(start)
        self.last = self.start
        self.expansions = 0
        self.rhs[self.goal] = 0.0
        self._push(self.goal)

    # -- queue (lazy deletion) ---------------------------------------------------------------------
    def _calc_key(self, s: int) -> tuple[float, float]:
        m = min(self.g[s], self.rhs[s])
        if m == INF:
            return (INF, INF)
        # rounded: g + h + km summed in different orders must compare equal, or a tie that
        # k2 should break is decided by a 1e-15 difference in k1 (and the search stops early)
        return (round(m + self.graph.octile(self.start, s) + self.km, KEY_DIGITS),
                round(m, KEY_DIGITS))

    def _push(self, s: int) -> None:
        k = self._calc_key(s)
        self.key[s] = k
        heapq.heappush(self.heap, (k[0], k[1], s))

    def _top(self) -> tuple[float, float, int] | None:
        heap, key = self.heap, self.key
        while heap:
            k1, k2, s = heap[0]
            if key[s] == (k1, k2):
                return heap[0]
            heapq.heappop(heap)  # stale entry
        return None

    def _update_vertex(self, u: int) -> None:
        if self.g[u] != self.rhs[u]:
            self._push(u)
        else:
            self.key[u] = None

    def _recompute_rhs(self, u: int) -> float:
        graph, g = self.graph, self.g
        best = INF
        for off, step, cut in graph.moves:
            c = graph.edge(u, off, step, cut)
            if c != INF:
                val = c + g[u + off]
                if val < best:
                    best = val
        return best

    # -- the algorithm -----------------------------------------------------------------------------
    def compute(self, max_expansions: int | None = None) -> int:
        """ComputeShortestPath; returns the number of expansions it made."""
        g, rhs, key, graph = self.g, self.rhs, self.key, self.graph
        cost, inner, moves = graph.cost, graph.inner, graph.moves
        start, goal = self.start, self.goal
        done = 0
        while True:
            top = self._top()
            if top is None:
                break
            if not ((top[0], top[1]) < self._calc_key(start) or rhs[start] > g[start]):
                break
            if max_expansions is not None and done >= max_expansions:
                break
            k_old = (top[0], top[1])
            u = top[2]
            k_new = self._calc_key(u)
            if k_old < k_new:
                self.key[u] = k_new
                heapq.heapreplace(self.heap, (k_new[0], k_new[1], u))
                continue
            heapq.heappop(self.heap)
            key[u] = None
            done += 1
            if g[u] > rhs[u]:  # overconsistent: settle
                g[u] = gu = rhs[u]
                for off, step, cut in moves:
                    s = u - off  # predecessor: s + off == u
                    if not inner[s] or s == goal:
                        continue
                    if cut is not None and (cost[s + cut[0]] == INF or cost[s + cut[1]] == INF):
                        continue
                    c = step * cost[u]
                    if c + gu < rhs[s]:
                        rhs[s] = c + gu
                        self._update_vertex(s)
            else:  # underconsistent: raise to inf, repair u and predecessors that used it
                g_old, g[u] = g[u], INF
                for off, step, cut in moves:
                    s = u - off
                    if not inner[s] or s == goal:
                        continue
                    c = graph.edge(s, off, step, cut)
                    if rhs[s] >= c + g_old - 1e-9:  # s may have taken its rhs through u
                        rhs[s] = self._recompute_rhs(s)
                        self._update_vertex(s)
                if u != goal:
                    rhs[u] = self._recompute_rhs(u)
                self._update_vertex(u)
        self.expansions += done
        return done

    def move_start(self, rc: Sequence[int]) -> None:
        """The robot is now in cell ``rc`` (call :meth:`compute` afterwards)."""
        self.start = self.graph.index(rc)

    def set_costs(self, rows: Iterable[int], cols: Iterable[int], values: Iterable[float]) -> int:
        """Change cell costs; updates every vertex with a changed outgoing edge. Returns the
        number of cells that really changed."""
        graph, cost, inner = self.graph, self.graph.cost, self.graph.inner
        touched: set[int] = set()
        changed = 0
        w = graph.width
        for r, c, val in zip(rows, cols, values, strict=True):
            idx = (int(r) + 1) * w + int(c) + 1
            val = float(val)
            if cost[idx] == val:
                continue
            cost[idx] = val
            changed += 1
            touched.update((idx, idx + 1, idx - 1, idx + w, idx - w,
                            idx + w + 1, idx + w - 1, idx - w + 1, idx - w - 1))
        if not changed:
            return 0
        self.km += graph.octile(self.last, self.start)
        self.last = self.start
        for u in sorted(touched):  # sorted: the same queue order on every run
            if inner[u] and u != self.goal:
                self.rhs[u] = self._recompute_rhs(u)
                self._update_vertex(u)
        return changed

    @property
    def path_cost(self) -> float:
        """Cost (cells) of the shortest path from the start to the goal; inf if none."""
        return self.rhs[self.start] if self.start != self.goal else 0.0

    def path(self, max_len: int | None = None) -> list[tuple[int, int]]:
        """Cells from the start to the goal by descending ``c + g``; [] if there is no path."""
        graph, g = self.graph, self.g
        if self.path_cost == INF:
            return []
        s, out, seen = self.start, [self.graph.cell(self.start)], {self.start}
        limit = max_len or len(g)
        while s != self.goal and len(out) < limit:
            best, nxt = INF, -1
            for off, step, cut in graph.moves:
                c = graph.edge(s, off, step, cut)
                if c != INF and c + g[s + off] < best:
                    best, nxt = c + g[s + off], s + off
            if nxt < 0 or nxt in seen:
                return []
            seen.add(nxt)
            out.append(graph.cell(nxt))
            s = nxt
        return out


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


class DStarLite(Planner):
    """D* Lite (Koenig & Likhachev 2002) on a sonar occupancy grid, freespace assumption."""

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
        Param("inflation_margin", 0.15, "m", "clearance beyond the robot radius that makes cells costly",
              minimum=0.0),
        # 1000, not 20: at 20 a path through a few inflated cells beat a detour of a few metres,
        # pure pursuit then clipped corners (paper worlds: 12 of 35 episodes stuck on a corner
        # with spinning wheels); at 1000 the band is used only when nothing else is free.
        Param("inflated_cost", 1000.0, "-", "step-cost factor of cells within radius + margin of an obstacle",
              minimum=1.0),
        Param("lookahead", 0.5, "m", "pure-pursuit lookahead distance along the path", minimum=0.05),
        Param("turn_in_place_deg", 60.0, "deg", "turn on the spot when the path is farther off the heading",
              minimum=0.0, maximum=180.0),
    )

    def reset(self, obs: Observation, rng: np.random.Generator) -> None:
        super().reset(obs, rng)
        p = self.settings
        self.grid = OccupancyGrid(obs.bounds, cell=p.cell, model=p.sonar_model)
        self.shape = self.grid.shape
        self.inflate_cells = (obs.robot.radius + p.inflation_margin) / p.cell
        self.struct = disk(self.inflate_cells)
        self.occupied = np.zeros(self.shape, dtype=bool)
        self.cost = np.ones(self.shape)
        self.goal_rc = self._clamp(self.grid.world_to_cell(obs.goal))
        self.search = DStarLiteSearch(self.cost, self._clamp(self.grid.world_to_cell(obs.pose[:2])),
                                      self.goal_rc)
        self.search.compute()
        self.cells: list[tuple[int, int]] = self.search.path()
        self.path_xy = self._to_world(self.cells, obs.goal)
        self.unreachable = False

    def _clamp(self, rc: np.ndarray) -> tuple[int, int]:
        h, w = self.shape
        return (int(min(max(rc[0], 0), h - 1)), int(min(max(rc[1], 0), w - 1)))

    def _to_world(self, cells: list[tuple[int, int]], goal: np.ndarray) -> np.ndarray:
        if not cells:
            return np.zeros((0, 2))
        rc = np.array(cells)
        xy = self.grid.cell_center(rc[:, 0], rc[:, 1])
        xy[-1] = goal  # end at the goal itself, not its cell centre
        return xy

    def _map_changes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Cells whose cost changed since the last cycle (rows, cols, new costs).

        Inflation is recomputed only in the window around the cells whose occupancy flipped.
        """
        occ = self.grid.values(copy=False) > self.settings.occupied_above
        occ[self.goal_rc] = False  # the goal cell is never lethal
        flipped = np.nonzero(occ != self.occupied)
        if len(flipped[0]) == 0:
            return flipped[0], flipped[1], np.zeros(0)
        self.occupied = occ
        n = self.struct.shape[0] // 2
        h, w = self.shape
        r0, r1 = max(flipped[0].min() - n, 0), min(flipped[0].max() + n + 1, h)
        c0, c1 = max(flipped[1].min() - n, 0), min(flipped[1].max() + n + 1, w)
        # the window's costs depend on occupancy up to n cells beyond it
        R0, R1, C0, C1 = max(r0 - n, 0), min(r1 + n, h), max(c0 - n, 0), min(c1 + n, w)
        sub = cell_costs(occ[R0:R1, C0:C1], self.inflate_cells, self.settings.inflated_cost)
        new = sub[r0 - R0:r1 - R0, c0 - C0:c1 - C0]
        old = self.cost[r0:r1, c0:c1]
        dr, dc = np.nonzero(new != old)
        vals = new[dr, dc]
        old[dr, dc] = vals
        return dr + r0, dc + c0, vals

    def act(self, obs: Observation) -> Command:
        if not self.update_path(obs):
            return STOP
        p = self.settings
        xy, goal = np.asarray(obs.pose[:2], dtype=float), np.asarray(obs.goal, dtype=float)
        v = min(p.v_max, obs.robot.v_max)
        if len(self.cells) <= 2:  # in the goal's cell or next to it
            d = float(np.hypot(*(goal - xy)))
            return steer(obs, math.atan2(goal[1] - xy[1], goal[0] - xy[0]), arrival_speed(d, v))
        return pure_pursuit(obs, self.path_xy, p.lookahead, v,
                            turn_in_place=math.radians(p.turn_in_place_deg))

    def update_path(self, obs: Observation) -> bool:
        """Fuse the sonars into the grid, repair the search and refresh :attr:`path_xy`; emits
        ``replan`` when the path ahead changed and ``unreachable`` (once per loss) when there is
        none. Returns whether a path exists. (``dwa_global`` follows the same path with DWA.)"""
        p = self.settings
        self.grid.update(obs.pose, obs.ranges, obs.robot.sonar)
        start = self._clamp(self.grid.world_to_cell(obs.pose[:2]))
        moved = start != self.search.graph.cell(self.search.start)
        self.search.move_start(start)
        rows, cols, vals = self._map_changes()
        changed = self.search.set_costs(rows, cols, vals) if len(rows) else 0
        self.search.compute()
        if changed or moved:
            old = self.cells
            self.cells = self.search.path()
            self.path_xy = self._to_world(self.cells, obs.goal)
            if changed and self.cells and _path_changed(old, self.cells):
                self.emit("replan", obs.t, changed_cells=int(changed),
                          cost_m=float(self.search.path_cost * p.cell))
        if not self.cells:
            if not self.unreachable:
                self.emit("unreachable", obs.t)
            self.unreachable = True
            return False
        self.unreachable = False
        return True

    def debug_state(self) -> dict[str, Any]:
        """The occupancy grid (:class:`~nav_bench.interface.GridState`, so plots draw it),
        ``cost`` (H, W) step-cost factors (inf lethal), ``path`` (N, 2) m."""
        if not hasattr(self, "grid"):
            return {}
        grids = GridState(pmo=self.grid.values(), bounds=self.grid.bounds, cell=self.grid.cell)
        return {**grids.state(), "cost": self.cost.copy(), "path": self.path_xy.copy()}


def _path_changed(old: list[tuple[int, int]], new: list[tuple[int, int]]) -> bool:
    """Does ``new`` leave the route of ``old``? Equal once ``new`` joins ``old``, from there on,
    means only the robot's own position moved (not a re-plan)."""
    if not old:
        return True
    where = {c: i for i, c in enumerate(old)}
    for j, cell in enumerate(new):
        if cell in where:
            return new[j:] != old[where[cell]:]
    return True
