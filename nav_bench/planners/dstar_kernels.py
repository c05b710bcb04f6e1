"""D* Lite's hot loops compiled with Numba (the optional ``fast`` extra: ``pip install nav-bench[fast]``).

Reference: S. Koenig and M. Likhachev, "D* Lite", AAAI-02, pp. 476-483, 2002: the optimised
version (Fig. 4) with the basic version's full ``rhs`` recomputation for vertices whose edges
changed, as :class:`nav_bench.planners.dstar_lite.DStarLiteSearch` writes it in Python. These
functions are that class's ``compute`` (ComputeShortestPath), the per-cell loop of
``set_costs`` and ``descend``, statement for statement: the same IEEE operations in the same
order (Numba uses no fast-math unless asked, and these functions do not ask), so ``g``,
``rhs``, the keys, the expansions and the paths are the Python code's bit for bit.
:class:`nav_bench.planners.dstar_lite.CompiledSearch` holds the state they work on.

The state (all flat over the grid padded with a lethal frame, ``n`` cells, row width ``w``):
``g``, ``rhs``, ``cost`` (float64; the frame's ``rhs`` is ``-inf``), ``inner`` (uint8, 1 on the
grid's own cells) and the priority queue as an indexed binary heap: ``heap[:size[0]]`` holds
vertices, ``pos[u]`` is ``u``'s place in it (-1: not queued), ``k1[u]``, ``k2[u]`` its key. The
Python search keeps a ``heapq`` with lazy deletion; both pop the queued vertex with the least
``(k1, k2, u)``, and a vertex is queued at most once, so they pop in the same order.

Imported only when a search chooses the kernel (importing Numba takes ~0.3 s). The compiled
functions are cached on disk (``cache=True``): in ``__pycache__`` beside this file, else in
the user's cache folder (``~/.cache/numba``), or in ``NUMBA_CACHE_DIR`` if set; where none is
writable they are compiled in each process instead (:func:`_kernel`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numba import njit

INF = math.inf
SQRT2 = math.sqrt(2.0)
_Q = 1.5 * 2.0 ** 23  # as in dstar_lite: (x + _Q) - _Q rounds x >= 0 to a multiple of 2**-29
_K = SQRT2 - 2.0  # octile distance: dr + dc + _K * min(dr, dc)


def _kernel(**options: Any) -> Callable[[Callable[..., Any]], Any]:
    """``numba.njit`` with an on-disk cache, or without one where Numba finds no writable
    cache folder (it raises at decoration then: a read-only install with no writable home)."""

    def compile_(fn: Callable[..., Any]) -> Any:
        try:
            return njit(cache=True, **options)(fn)
        except RuntimeError:  # "cannot cache function ...: no locator available"
            return njit(cache=False, **options)(fn)

    return compile_


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
def _sift_up(heap: np.ndarray, pos: np.ndarray, k1: np.ndarray, k2: np.ndarray, i: int) -> None:
    u = heap[i]
    while i > 0:
        parent = (i - 1) >> 1
        p = heap[parent]
        if not _before(k1, k2, u, p):
            break
        heap[i] = p
        pos[p] = i
        i = parent
    heap[i] = u
    pos[u] = i


@_kernel()
def _sift_down(heap: np.ndarray, pos: np.ndarray, k1: np.ndarray, k2: np.ndarray, size: int,
               i: int) -> None:
    u = heap[i]
    while True:
        child = 2 * i + 1
        if child >= size:
            break
        if child + 1 < size and _before(k1, k2, heap[child + 1], heap[child]):
            child += 1
        c = heap[child]
        if not _before(k1, k2, c, u):
            break
        heap[i] = c
        pos[c] = i
        i = child
    heap[i] = u
    pos[u] = i


@_kernel()
def queue_set(heap: np.ndarray, pos: np.ndarray, k1: np.ndarray, k2: np.ndarray, size: np.ndarray,
              u: int, n1: float, n2: float) -> None:
    """Queue ``u`` with key (n1, n2), or move it there if it is queued."""
    k1[u], k2[u] = n1, n2
    i = pos[u]
    if i < 0:
        i = size[0]
        size[0] += 1
        heap[i] = u
        _sift_up(heap, pos, k1, k2, i)
        return
    _sift_up(heap, pos, k1, k2, i)
    _sift_down(heap, pos, k1, k2, size[0], pos[u])


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
    x = heap[last]  # the last vertex fills the hole, then moves up or down to its place
    heap[i] = x
    pos[x] = i
    _sift_up(heap, pos, k1, k2, i)
    _sift_down(heap, pos, k1, k2, last, pos[x])


# -- D* Lite's pieces ----------------------------------------------------------------------------
@_kernel(inline="always")
def _key1(m: float, u: int, sr: int, sc: int, w: int, km: float) -> float:
    """k1 = (m + h + km) rounded, h the octile distance from the start (as ``_queue_key``)."""
    dr, dc = u // w - sr, u % w - sc
    dr, dc = (dr if dr > 0 else -dr), (dc if dc > 0 else -dc)
    return (m + (dr + dc + _K * (dr if dr < dc else dc)) + km + _Q) - _Q


@_kernel()
def recompute_rhs(cost: np.ndarray, g: np.ndarray, w: int, s: int) -> float:
    """min over the successors ``v`` of c(s, v) + g(v), in ``_recompute_rhs``'s order."""
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
        gs, rs = g[start], rhs[start]
        ms = gs if gs < rs else rs
        ks1 = ks2 = INF
        if ms != INF:
            ks1, ks2 = (ms + km + _Q) - _Q, (ms + _Q) - _Q
        if size[0] == 0:
            settled = True
            break
        u = heap[0]
        t1, t2 = k1[u], k2[u]
        if not (t1 < ks1 or (t1 == ks1 and t2 < ks2) or rs > gs):
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
            k1[u], k2[u] = n1, n2  # re-key: the key only grows, so sift down from the top
            _sift_down(heap, pos, k1, k2, size[0], 0)
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


_FULL, _LOWERED = 1, 2  # marks of set_costs: rhs recomputed from all successors / lowered in place


@_kernel()
def _mark(mark: np.ndarray, marked: np.ndarray, count: int, s: int, kind: int) -> int:
    """Add ``s`` to the set ``kind`` (a bit of ``mark[s]``); returns the new count of ``marked``."""
    if mark[s] == 0:
        marked[count] = s
        count += 1
    mark[s] |= kind
    return count


@_kernel()
def set_costs(flat: np.ndarray, values: np.ndarray, cost: np.ndarray, g: np.ndarray, rhs: np.ndarray,
              inner: np.ndarray, heap: np.ndarray, pos: np.ndarray, k1: np.ndarray, k2: np.ndarray,
              size: np.ndarray, mark: np.ndarray, w: int, goal: int, start: int,
              km: float) -> np.ndarray:
    """``DStarLiteSearch.set_costs``' loop: set ``cost[flat[i]] = values[i]`` in turn, lower or
    recompute the predecessors' rhs (Fig. 4's optimised update) and, if any cost changed, queue
    the inconsistent ones with ``km`` (the grown value: the caller commits it when something
    changed). ``mark`` (int8, n) is scratch, all 0 before and after. Returns the flat indices
    of the cells whose cost changed, in order."""
    changed = np.empty(len(flat), dtype=np.int64)
    marked = np.empty(9 * len(flat), dtype=np.int64)
    nc = count = 0
    for i in range(len(flat)):
        v, val = flat[i], values[i]
        was = cost[v]
        if was == val:
            continue
        cost[v] = val
        changed[nc] = v
        nc += 1
        if was == INF or val == INF:
            for s in (v, v + 1, v - 1, v + w, v - w, v + w + 1, v + w - 1, v - w + 1, v - w - 1):
                count = _mark(mark, marked, count, s, _FULL)
            continue
        gv = g[v]
        if gv == INF:
            continue
        left, right = cost[v - 1] != INF, cost[v + 1] != INF
        down, up = cost[v - w] != INF, cost[v + w] != INF
        if val < was:  # cheaper: lower the predecessors' rhs
            cand = val + gv
            for s in (v - 1, v - w, v + 1, v + w):
                if cand < rhs[s]:
                    rhs[s] = cand
                    count = _mark(mark, marked, count, s, _LOWERED)
            cand = SQRT2 * val + gv
            if left and down and cand < rhs[v - w - 1]:
                rhs[v - w - 1] = cand
                count = _mark(mark, marked, count, v - w - 1, _LOWERED)
            if left and up and cand < rhs[v + w - 1]:
                rhs[v + w - 1] = cand
                count = _mark(mark, marked, count, v + w - 1, _LOWERED)
            if right and down and cand < rhs[v - w + 1]:
                rhs[v - w + 1] = cand
                count = _mark(mark, marked, count, v - w + 1, _LOWERED)
            if right and up and cand < rhs[v + w + 1]:
                rhs[v + w + 1] = cand
                count = _mark(mark, marked, count, v + w + 1, _LOWERED)
            continue
        through = was + gv - 1e-9  # dearer: recompute the rhs that may have gone through v
        for s in (v - 1, v - w, v + 1, v + w):
            if rhs[s] >= through:
                count = _mark(mark, marked, count, s, _FULL)
        through = SQRT2 * was + gv - 1e-9
        if left:
            if down and rhs[v - w - 1] >= through:
                count = _mark(mark, marked, count, v - w - 1, _FULL)
            if up and rhs[v + w - 1] >= through:
                count = _mark(mark, marked, count, v + w - 1, _FULL)
        if right:
            if down and rhs[v - w + 1] >= through:
                count = _mark(mark, marked, count, v - w + 1, _FULL)
            if up and rhs[v + w + 1] >= through:
                count = _mark(mark, marked, count, v + w + 1, _FULL)
    if nc > 0:
        mark[goal] = 0  # the goal's rhs stays 0 and it is not queued
        for j in range(count):
            u = marked[j]
            if mark[u] & _FULL and inner[u]:
                rhs[u] = recompute_rhs(cost, g, w, u)
        sr, sc = start // w, start % w
        for j in range(count):
            u = marked[j]
            if mark[u] == 0:
                continue
            gu, ru = g[u], rhs[u]
            if gu == ru or not inner[u]:
                queue_remove(heap, pos, k1, k2, size, u)
                continue
            m = gu if gu < ru else ru
            queue_set(heap, pos, k1, k2, size, u, _key1(m, u, sr, sc, w, km), (m + _Q) - _Q)
    for j in range(count):
        mark[marked[j]] = 0
    return changed[:nc]


@_kernel()
def descend(cost: np.ndarray, g: np.ndarray, w: int, start: int, goal: int, limit: int,
            index: np.ndarray, after: int, seen: np.ndarray) -> np.ndarray:
    """``DStarLiteSearch.descend``: flat indices from the start by descending c + g, the first
    of equal successors in MOVES' order, at most ``limit``; stops at the first cell after the
    start whose ``index`` is above ``after`` (``index`` empty: no join); empty if there is no
    descent (a dead end or a loop). ``seen`` (int8, n) is scratch, all 0 before and after."""
    out = np.empty(min(limit, 1024), dtype=np.int64)
    out[0] = start
    n = 1
    seen[start] = 1
    s = start
    join = len(index) > 0
    failed = False
    while s != goal and n < limit:
        if join and n > 1 and index[s] > after:
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
        if n == len(out):
            grown = np.empty(2 * n, dtype=np.int64)
            grown[:n] = out
            out = grown
        out[n] = nxt
        n += 1
        s = nxt
    for j in range(n):
        seen[out[j]] = 0
    return out[:0] if failed else out[:n]
