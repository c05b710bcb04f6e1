"""D* Lite's hot loops compiled with Numba (the optional ``fast`` extra: ``pip install nav-bench[fast]``).

Reference: S. Koenig and M. Likhachev, "D* Lite", AAAI-02, pp. 476-483, 2002: the optimised
version (Fig. 4) with the basic version's full ``rhs`` recomputation for vertices whose edges
changed, as :class:`nav_bench.planners.dstar_lite.DStarLiteSearch` writes it in Python. These
functions are that class's ``compute`` (ComputeShortestPath) and the per-cell loop of
``set_costs``, statement for statement, and :mod:`~nav_bench.planners.dstar_loops`' functions
(``recompute_rhs``, ``descend``: one source for both) compiled: the same IEEE operations in the same
order (Numba uses no fast-math unless asked, and these functions do not ask), so ``g``,
``rhs``, the keys, the expansions and the paths are the Python code's bit for bit.
:class:`nav_bench.planners.dstar_lite.CompiledSearch` holds the state they work on.

The state (all flat over the grid padded with a lethal frame, ``n`` cells, row width ``w``):
``g``, ``rhs``, ``cost`` (float64; the frame's ``rhs`` is ``-inf``), ``inner`` (uint8, 1 on the
grid's own cells) and the priority queue as an indexed binary heap: ``heap[:size[0]]`` holds
vertices, ``pos[u]`` is ``u``'s place in it (-1: not queued), ``k1[u]``, ``k2[u]`` its key. The
Python search keeps a ``heapq`` with lazy deletion; both pop the queued vertex with the least
``(k1, k2, u)``, and a vertex is queued at most once, so they pop in the same order.

Imported only when a search chooses the kernel (:func:`nav_bench.compiled.load`), compiled and
cached by :func:`nav_bench.compiled.kernel`.
"""

from __future__ import annotations

import numpy as np

from nav_bench.compiled import kernel as _kernel
from nav_bench.planners import dstar_loops as loops
from nav_bench.planners.dstar_loops import _K, _Q, INF, SQRT2


# -- the indexed heap ----------------------------------------------------------------------------
@_kernel(inline="always")
def _before(k1: np.ndarray, k2: np.ndarray, a: int, b: int) -> bool:
    """Does vertex ``a``'s key (k1, k2, a) come before ``b``'s (tuple order, as heapq's)?"""
    if k1[a] != k1[b]:
        return k1[a] < k1[b]
    if k2[a] != k2[b]:
        return k2[a] < k2[b]
    return a < b


@_kernel()
def _sift(heap: np.ndarray, pos: np.ndarray, k1: np.ndarray, k2: np.ndarray, size: int,
          i: int) -> None:
    """Move the vertex at ``heap[i]`` up toward the root while it comes before its parent, else
    down while a child comes before it (a vertex that moved up is before all below it)."""
    u = heap[i]
    while i > 0 and _before(k1, k2, u, heap[(i - 1) >> 1]):
        heap[i] = heap[(i - 1) >> 1]
        pos[heap[i]] = i
        i = (i - 1) >> 1
    while True:
        child = 2 * i + 1
        if child + 1 < size and _before(k1, k2, heap[child + 1], heap[child]):
            child += 1
        if child >= size or not _before(k1, k2, heap[child], u):
            break
        heap[i] = heap[child]
        pos[heap[i]] = i
        i = child
    heap[i] = u
    pos[u] = i


@_kernel()
def queue_set(heap: np.ndarray, pos: np.ndarray, k1: np.ndarray, k2: np.ndarray, size: np.ndarray,
              u: int, n1: float, n2: float) -> None:
    """Queue ``u`` with key (n1, n2), or move it there if it is queued."""
    k1[u], k2[u] = n1, n2
    i = pos[u]
    if i < 0:  # a new leaf
        i = size[0]
        size[0] += 1
        heap[i] = u
    _sift(heap, pos, k1, k2, size[0], i)


@_kernel()
def queue_remove(heap: np.ndarray, pos: np.ndarray, k1: np.ndarray, k2: np.ndarray,
                 size: np.ndarray, u: int) -> None:
    """Take ``u`` out of the queue (nothing if it is not queued)."""
    i = pos[u]
    if i < 0:
        return
    pos[u] = -1
    size[0] -= 1
    last = size[0]
    if i == last:
        return
    heap[i] = heap[last]  # the last vertex fills the hole, then moves up or down to its place
    _sift(heap, pos, k1, k2, last, i)


# -- D* Lite's pieces ----------------------------------------------------------------------------
@_kernel(inline="always")
def _key1(m: float, u: int, sr: int, sc: int, w: int, km: float) -> float:
    """k1 = (m + h + km) rounded, h the octile distance from the start (as ``_queue_key``)."""
    dr, dc = u // w - sr, u % w - sc
    dr, dc = (dr if dr > 0 else -dr), (dc if dc > 0 else -dc)
    return (m + (dr + dc + _K * (dr if dr < dc else dc)) + km + _Q) - _Q


recompute_rhs = _kernel()(loops.recompute_rhs)  # min over s's successors of c(s, v) + g(v)


@_kernel()
def update_vertex(g: np.ndarray, rhs: np.ndarray, heap: np.ndarray, pos: np.ndarray,
                  k1: np.ndarray, k2: np.ndarray, size: np.ndarray, u: int, start: int, w: int,
                  km: float) -> None:
    """Queue ``u`` with its key if it is inconsistent, else drop it (``_update_vertex``)."""
    gu, ru = g[u], rhs[u]
    if gu == ru:
        queue_remove(heap, pos, k1, k2, size, u)
        return
    m = gu if gu < ru else ru
    queue_set(heap, pos, k1, k2, size, u, _key1(m, u, start // w, start % w, w, km), (m + _Q) - _Q)


@_kernel()
def _lower(g: np.ndarray, rhs: np.ndarray, heap: np.ndarray, pos: np.ndarray, k1: np.ndarray,
           k2: np.ndarray, size: np.ndarray, s: int, val: float, sr: int, sc: int, w: int,
           km: float) -> None:
    """rhs(s) falls to val (the closure ``lower`` of ``compute``)."""
    rhs[s] = val
    gs = g[s]
    if gs == val:
        queue_remove(heap, pos, k1, k2, size, s)
        return
    m = gs if gs < val else val
    queue_set(heap, pos, k1, k2, size, s, _key1(m, s, sr, sc, w, km), (m + _Q) - _Q)


@_kernel()
def _raise(cost: np.ndarray, g: np.ndarray, rhs: np.ndarray, heap: np.ndarray, pos: np.ndarray,
           k1: np.ndarray, k2: np.ndarray, size: np.ndarray, s: int, val: float, start: int, w: int,
           km: float) -> None:
    """s may have taken its rhs through the raised vertex: recompute it and queue it."""
    if rhs[s] >= val:
        rhs[s] = recompute_rhs(cost, g, w, s)
        update_vertex(g, rhs, heap, pos, k1, k2, size, s, start, w, km)


@_kernel(inline="always")
def _start_key(gs: float, rs: float, km: float) -> tuple[float, float]:
    """The start's key (its h is 0), rounded as every key; (inf, inf) while it has no path."""
    ms = gs if gs < rs else rs
    if ms == INF:
        return INF, INF
    return (ms + km + _Q) - _Q, (ms + _Q) - _Q


@_kernel()
def compute(g: np.ndarray, rhs: np.ndarray, cost: np.ndarray, heap: np.ndarray, pos: np.ndarray,
            k1: np.ndarray, k2: np.ndarray, size: np.ndarray, start: int, w: int, km: float,
            budget: int) -> tuple[int, int, bool, np.ndarray]:
    """ComputeShortestPath with at most ``budget`` queue steps (-1: no limit), as
    ``DStarLiteSearch.compute`` writes it. Returns (expansions, queue steps, settled, the
    vertices whose g it set, in order)."""
    sr, sc = start // w, start % w
    touched = np.empty(64, dtype=np.int64)
    done = steps = 0
    settled = False
    while True:
        ks1, ks2 = _start_key(g[start], rhs[start], km)
        if size[0] == 0:
            settled = True
            break
        u = heap[0]
        t1, t2 = k1[u], k2[u]
        if not (t1 < ks1 or (t1 == ks1 and t2 < ks2) or rhs[start] > g[start]):
            settled = True
            break
        if steps == budget:
            break
        steps += 1
        gu, ru = g[u], rhs[u]
        mu = gu if gu < ru else ru
        n1 = _key1(mu, u, sr, sc, w, km)
        n2 = (mu + _Q) - _Q
        if t1 < n1 or (t1 == n1 and t2 < n2):
            k1[u], k2[u] = n1, n2  # re-key: the key only grows, so it moves down from the top
            _sift(heap, pos, k1, k2, size[0], 0)
            continue
        queue_remove(heap, pos, k1, k2, size, u)
        if done == len(touched):
            grown = np.empty(2 * len(touched), dtype=np.int64)
            grown[:done] = touched
            touched = grown
        touched[done] = u
        done += 1
        cu = cost[u]
        if gu > ru:  # overconsistent: settle, lower the predecessors it is now cheaper through
            g[u] = ru
            if cu == INF:
                continue
            val = cu + ru
            if val < rhs[u - 1]:
                _lower(g, rhs, heap, pos, k1, k2, size, u - 1, val, sr, sc, w, km)
            if val < rhs[u - w]:
                _lower(g, rhs, heap, pos, k1, k2, size, u - w, val, sr, sc, w, km)
            if val < rhs[u + 1]:
                _lower(g, rhs, heap, pos, k1, k2, size, u + 1, val, sr, sc, w, km)
            if val < rhs[u + w]:
                _lower(g, rhs, heap, pos, k1, k2, size, u + w, val, sr, sc, w, km)
            val = SQRT2 * cu + ru
            if cost[u - 1] != INF:
                if cost[u - w] != INF and val < rhs[u - w - 1]:
                    _lower(g, rhs, heap, pos, k1, k2, size, u - w - 1, val, sr, sc, w, km)
                if cost[u + w] != INF and val < rhs[u + w - 1]:
                    _lower(g, rhs, heap, pos, k1, k2, size, u + w - 1, val, sr, sc, w, km)
            if cost[u + 1] != INF:
                if cost[u - w] != INF and val < rhs[u - w + 1]:
                    _lower(g, rhs, heap, pos, k1, k2, size, u - w + 1, val, sr, sc, w, km)
                if cost[u + w] != INF and val < rhs[u + w + 1]:
                    _lower(g, rhs, heap, pos, k1, k2, size, u + w + 1, val, sr, sc, w, km)
        else:  # underconsistent: raise to inf, repair u and the predecessors that used it
            g[u] = INF
            if cu != INF:
                left, right = cost[u - 1] != INF, cost[u + 1] != INF
                down, up = cost[u - w] != INF, cost[u + w] != INF
                val = cu + gu - 1e-9
                _raise(cost, g, rhs, heap, pos, k1, k2, size, u - 1, val, start, w, km)
                _raise(cost, g, rhs, heap, pos, k1, k2, size, u - w, val, start, w, km)
                _raise(cost, g, rhs, heap, pos, k1, k2, size, u + 1, val, start, w, km)
                _raise(cost, g, rhs, heap, pos, k1, k2, size, u + w, val, start, w, km)
                val = SQRT2 * cu + gu - 1e-9
                if left and down:
                    _raise(cost, g, rhs, heap, pos, k1, k2, size, u - w - 1, val, start, w, km)
                if right and down:
                    _raise(cost, g, rhs, heap, pos, k1, k2, size, u - w + 1, val, start, w, km)
                if right and up:
                    _raise(cost, g, rhs, heap, pos, k1, k2, size, u + w + 1, val, start, w, km)
                if left and up:
                    _raise(cost, g, rhs, heap, pos, k1, k2, size, u + w - 1, val, start, w, km)
            update_vertex(g, rhs, heap, pos, k1, k2, size, u, start, w, km)
    return done, steps, settled, touched[:done]


apply_costs = _kernel()(loops.apply_costs)  # set_costs' per-cell loop


@_kernel()
def set_costs(flat: np.ndarray, values: np.ndarray, cost: np.ndarray, g: np.ndarray, rhs: np.ndarray,
              inner: np.ndarray, heap: np.ndarray, pos: np.ndarray, k1: np.ndarray, k2: np.ndarray,
              size: np.ndarray, mark: np.ndarray, w: int, goal: int, start: int,
              km: float) -> list[int]:
    """``DStarLiteSearch.set_costs`` after its conversions: the costs applied
    (:func:`~nav_bench.planners.dstar_loops.apply_costs`) and, if any changed, the marked
    vertices' rhs recomputed and the inconsistent ones queued with ``km`` (the grown value:
    the caller commits it when something changed). ``mark`` (int8, n) is scratch, all 0 before
    and after. Returns the flat indices of the cells whose cost changed, in order."""
    changed, marked = apply_costs(flat, values, cost, g, rhs, w, mark)
    if len(changed) == 0:
        return changed
    mark[goal] = 0  # the goal's rhs stays 0 and it is not queued
    for u in marked:
        if mark[u] & loops.FULL and inner[u]:
            rhs[u] = recompute_rhs(cost, g, w, u)
    sr, sc = start // w, start % w
    for u in marked:
        if mark[u] == 0:
            continue
        mark[u] = 0
        if g[u] == rhs[u] or not inner[u]:
            queue_remove(heap, pos, k1, k2, size, u)
        else:
            m = g[u] if g[u] < rhs[u] else rhs[u]
            queue_set(heap, pos, k1, k2, size, u, _key1(m, u, sr, sc, w, km), (m + _Q) - _Q)
    return changed


descend = _kernel()(loops.descend)  # the path from the start by descending c + g
