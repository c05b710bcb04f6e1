"""D* Lite's per-vertex loops as plain functions of indexable sequences, one source for both
searches: :class:`~nav_bench.planners.dstar_lite.DStarLiteSearch` calls them on Python lists,
:mod:`~nav_bench.planners.dstar_kernels` compiles these very functions with Numba for
:class:`~nav_bench.planners.dstar_lite.CompiledSearch`'s NumPy arrays. The same operations in
the same order, so both give the same values bit for bit.

The grid is flat and padded with a lethal frame (row width ``w``): ``cost`` holds the step-cost
factors (``inf`` lethal), ``g`` the costs to the goal. Moving from ``s`` to a neighbour ``v``
costs ``cost[v]`` straight and ``sqrt 2 * cost[v]`` diagonally; a diagonal may not cut past a
lethal cell (Koenig & Likhachev's D* Lite, AAAI 2002, on an 8-connected grid).
"""

from __future__ import annotations

import math
from typing import Any

INF = math.inf
SQRT2 = math.sqrt(2.0)
_Q = 1.5 * 2.0 ** 23  # (x + _Q) - _Q rounds x >= 0 to a multiple of 2**-29 (~2e-9) up to 2**22
_K = SQRT2 - 2.0  # octile distance: dr + dc + _K * min(dr, dc)


def recompute_rhs(cost: Any, g: Any, w: int, s: int) -> float:
    """min over the successors ``v`` of ``s`` of c(s, v) + g(v): the straight steps (right, up,
    left, down), then the diagonals not past a lethal cell, in MOVES' order (written out: the
    search's most frequent call)."""
    right, up, left, down = cost[s + 1], cost[s + w], cost[s - 1], cost[s - w]
    best = right + g[s + 1]
    val = up + g[s + w]
    if val < best:
        best = val
    val = left + g[s - 1]
    if val < best:
        best = val
    val = down + g[s - w]
    if val < best:
        best = val
    if up != INF:
        if right != INF:
            val = SQRT2 * cost[s + w + 1] + g[s + w + 1]
            if val < best:
                best = val
        if left != INF:
            val = SQRT2 * cost[s + w - 1] + g[s + w - 1]
            if val < best:
                best = val
    if down != INF:
        if left != INF:
            val = SQRT2 * cost[s - w - 1] + g[s - w - 1]
            if val < best:
                best = val
        if right != INF:
            val = SQRT2 * cost[s - w + 1] + g[s - w + 1]
            if val < best:
                best = val
    return best


def descend(cost: Any, g: Any, w: int, start: int, goal: int, limit: int, index: Any, after: int,
            seen: Any) -> list[int]:
    """Flat indices from ``start`` toward ``goal`` (at most ``limit``) by descending c + g, the
    first of equal successors in MOVES' order; [] at a dead end or a loop.

    ``index``: flat index -> index in an old path (-1: not on it), or empty for none; the
    descent stops at the first cell after the start that ``index`` maps above ``after``.
    ``seen``: scratch, one entry per cell, all 0 before and after the call."""
    out = [start]
    seen[start] = 1
    s = start
    join = len(index) > 0
    failed = False
    while s != goal and len(out) < limit:
        if join and len(out) > 1 and index[s] > after:
            break
        right, up, left, down = cost[s + 1], cost[s + w], cost[s - 1], cost[s - w]
        best, nxt = right + g[s + 1], s + 1
        val = up + g[s + w]
        if val < best:
            best, nxt = val, s + w
        val = left + g[s - 1]
        if val < best:
            best, nxt = val, s - 1
        val = down + g[s - w]
        if val < best:
            best, nxt = val, s - w
        if up != INF:
            if right != INF:
                val = SQRT2 * cost[s + w + 1] + g[s + w + 1]
                if val < best:
                    best, nxt = val, s + w + 1
            if left != INF:
                val = SQRT2 * cost[s + w - 1] + g[s + w - 1]
                if val < best:
                    best, nxt = val, s + w - 1
        if down != INF:
            if left != INF:
                val = SQRT2 * cost[s - w - 1] + g[s - w - 1]
                if val < best:
                    best, nxt = val, s - w - 1
            if right != INF:
                val = SQRT2 * cost[s - w + 1] + g[s - w + 1]
                if val < best:
                    best, nxt = val, s - w + 1
        if best == INF or seen[nxt]:
            failed = True
            break
        seen[nxt] = 1
        out.append(nxt)
        s = nxt
    for v in out:
        seen[v] = 0
    return out[:0] if failed else out


FULL, LOWERED = 1, 2  # apply_costs' marks: rhs to recompute from all successors / lowered in place


def apply_costs(flat: Any, values: Any, cost: Any, g: Any, rhs: Any, w: int,
                mark: Any) -> tuple[list[int], list[int]]:
    """The per-cell loop of ``set_costs``: set ``cost[flat[i]] = values[i]`` in turn and update
    the predecessors of each cell that really changed (the paper's optimised update, Fig. 4).

    An edge into ``v`` that got cheaper lowers the predecessor's ``rhs`` at once (mark
    ``LOWERED``); one that got dearer marks the predecessors whose ``rhs`` may have gone through
    ``v`` (``FULL``: recompute from all successors). A cell that becomes or stops being lethal
    also changes the diagonal edges cutting past it: its whole 3 x 3 block is ``FULL``. A frame
    cell's ``rhs`` (-inf) and the goal's (0) are never above a candidate nor reached through
    ``v``. ``mark``: one entry per cell, 0 before the call; the caller clears the cells listed.
    Returns (the cells whose cost changed, in order; the marked cells, each once)."""
    changed = [0 for _ in range(0)]  # (typed empty lists, for Numba as for Python)
    marked = [0 for _ in range(0)]
    for i in range(len(flat)):
        v, val = flat[i], values[i]
        was = cost[v]
        if was == val:
            continue
        cost[v] = val
        changed.append(v)
        if was == INF or val == INF:
            for s in (v, v + 1, v - 1, v + w, v - w, v + w + 1, v + w - 1, v - w + 1, v - w - 1):
                if not mark[s]:
                    marked.append(s)
                mark[s] |= FULL
            continue
        gv = g[v]
        if gv == INF:
            continue  # no rhs goes through v, and a cheaper v cannot lower one yet
        left, right = cost[v - 1] != INF, cost[v + 1] != INF
        down, up = cost[v - w] != INF, cost[v + w] != INF
        diagonals = ((v - w - 1, left and down), (v + w - 1, left and up),
                     (v - w + 1, right and down), (v + w + 1, right and up))
        if val < was:  # cheaper: lower the predecessors' rhs
            cand = val + gv
            for s in (v - 1, v - w, v + 1, v + w):
                if cand < rhs[s]:
                    rhs[s] = cand
                    if not mark[s]:
                        marked.append(s)
                    mark[s] |= LOWERED
            cand = SQRT2 * val + gv
            for s, ok in diagonals:
                if ok and cand < rhs[s]:
                    rhs[s] = cand
                    if not mark[s]:
                        marked.append(s)
                    mark[s] |= LOWERED
            continue
        through = was + gv - 1e-9  # dearer: recompute the rhs that may have gone through v
        for s in (v - 1, v - w, v + 1, v + w):
            if rhs[s] >= through:
                if not mark[s]:
                    marked.append(s)
                mark[s] |= FULL
        through = SQRT2 * was + gv - 1e-9
        for s, ok in diagonals:
            if ok and rhs[s] >= through:
                if not mark[s]:
                    marked.append(s)
                mark[s] |= FULL
    return changed, marked
