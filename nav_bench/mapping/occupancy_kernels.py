"""The sonar map's update compiled with Numba (the optional ``fast`` extra: ``pip install nav-bench[fast]``).

These functions are the per-cell NumPy code of :class:`nav_bench.mapping.occupancy.OccupancyGrid`
(``_cone_cells``' cone, range and grid tests, ``_independent_runs``, the non-``exp`` part of
``_fuse``, the values' write-back) as loops over the candidate cells: the same IEEE operations on
the same operands in the same order (Numba uses no fast-math unless asked, and these functions do
not ask), so the log-odds and values are the NumPy code's bit for bit. The ``arctan2`` of Elfes'
weight and the ``exp`` of Konolige's blame and of the values stay in NumPy, between the kernels:
their last bits differ between NumPy's SIMD loops and the C library Numba calls
(:mod:`nav_bench.compiled`).

An update is: :func:`cone_cells` (the candidates read from the cone tables, the kept cells and
the runs of sonars to fuse one after the other) -> NumPy ``arctan2`` -> :func:`elfes_weight`
("elfes") -> per run: :func:`arc_log_odds` -> NumPy ``exp`` -> :func:`fuse`; then
(:func:`negated_log_odds` if there were several runs) -> NumPy ``exp`` -> :func:`write_values`.
One liberty, which cannot change a result: :func:`cone_cells` skips the ``hypot`` of a cell
whose sum of squares, with a margin, proves it seen through (:func:`_squared_near`).

Imported only when a grid chooses the kernels (:func:`nav_bench.compiled.load`), compiled and
cached by :func:`nav_bench.compiled.kernel`.
"""

from __future__ import annotations

import math

import numpy as np

from nav_bench.compiled import kernel as _kernel

# columns of the per-sonar rows (OccupancyGrid._reading's _SONAR_ROWS)
_COL, _ROW, _FLAT, _CX, _CY, _UX, _UY, _ECHO, _FREE, _START, _LENGTH, _REACH = range(12)


@_kernel(inline="always")
def _bisect_right(a: np.ndarray, x: float, lo: int, hi: int) -> int:
    """Python's ``bisect.bisect_right(a, x, lo, hi)``: the first index in ``[lo, hi)`` whose
    value is above ``x`` (``hi`` if none), ``a[lo:hi]`` ascending."""
    while lo < hi:
        mid = (lo + hi) // 2
        if x < a[mid]:
            hi = mid
        else:
            lo = mid + 1
    return lo


@_kernel(inline="always")
def _squared_near(echo: float, free: float, half_t: float) -> float:
    """A squared distance (m^2) below which ``dx^2 + dy^2`` (as computed) proves a cone cell
    seen through and off the arc, so its ``hypot`` need not be computed (-1: none).

    ``hypot`` and the sum of squares are both within 1e-15 relative of the true values; a
    margin of 1e-9 relative, far above that and above the echo's ulp, keeps the proof exact
    (the tests compare both paths bit for bit)."""
    limit = free if echo == -math.inf else min(free, echo - half_t)
    if not limit > 1e-6 * max(1.0, echo):
        return -1.0
    near = limit * (1.0 - 1e-9)
    return near * near


@_kernel()
def cone_cells(tables: np.ndarray, table_dist: np.ndarray, rows: np.ndarray, disc_c: np.ndarray,
               disc_r: np.ndarray, cell: float, tan_half: float, half_t: float, r0: int, c0: int,
               height: int, width: int, edges: bool, span: int, owner: np.ndarray
               ) -> tuple[int, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:
    """The cells a reading updates: the candidates that pass the cone, range and (``edges``)
    grid tests, in the candidates' order.

    Args:
        tables, table_dist: the cone tables' disc cells and their distances from the disc's
            centre (m), end to end (``OccupancyGrid._all_tables``).
        rows: (K, 12) per sonar: its cell's column, row and flat offsets from the robot's cell,
            the robot cell's centre less the sonar's position (m), its axis (ux, uy), its echo
            range (m; -inf: no echo), the range below which a cone cell is seen through (m),
            the start and length of its table in ``tables`` and its reach (m): its candidates
            are the table's cells within reach (``bisect_right``).
        disc_c, disc_r: the disc's column and row offsets (cells), as floats.
        cell, tan_half, half_t: cell side (m), tan(cone / 2), half the echo arc's thickness (m).
        r0, c0: the robot's cell; height, width: the grid's.
        span: no candidate is farther from the robot's cell along a row or a column.
        owner: (>= (2 span + 1)^2,) scratch over the square of cells within ``span`` of the
            robot's, -1 everywhere; left so.

    Returns ``(n, idx, sonar, occ, off_axis, along, bounds, runs)``, the first ``n`` entries of
    each array meaningful: flat grid index, sonar, on the echo arc, lateral distance from the
    axis less half a cell (>= 0, m), distance along the axis (m); the runs of sonars whose cones
    share no cell (``_independent_runs``) as entry bounds ``bounds[:runs + 1]``.
    """
    count = len(rows)
    m = 0
    stops = np.empty(count, dtype=np.int64)  # the end of each sonar's candidates in tables
    for k in range(count):
        first = int(rows[k, _START])
        stops[k] = _bisect_right(table_dist, rows[k, _REACH], first, first + int(rows[k, _LENGTH]))
        m += stops[k] - first
    half_cell = cell / 2
    idx = np.empty(m, dtype=np.int64)
    sonar = np.empty(m, dtype=np.int64)
    occ = np.empty(m, dtype=np.bool_)
    off_axis = np.empty(m)
    along_kept = np.empty(m)
    bounds = np.empty(count + 1, dtype=np.int64)
    square = np.empty(m, dtype=np.int64)  # each kept cell's place in owner
    side = 2 * span + 1
    bounds[0] = 0
    runs = 0
    n = 0
    base = r0 * width + c0
    for k in range(count):
        hc, hr = rows[k, _COL], rows[k, _ROW]
        cx, cy, ux, uy = rows[k, _CX], rows[k, _CY], rows[k, _UX], rows[k, _UY]
        echo, free = rows[k, _ECHO], rows[k, _FREE]
        near = _squared_near(echo, free, half_t)
        first = n
        new_run = False
        for j in range(int(rows[k, _START]), stops[k]):
            d = tables[j]
            col = disc_c[d] + hc  # whole numbers: exact
            row = disc_r[d] + hr
            dx = col * cell + cx
            dy = row * cell + cy
            along = dx * ux + dy * uy
            lateral = abs(dy * ux - dx * uy)
            if not (lateral <= along * tan_half + half_cell and along > 0):  # not in the cone
                continue
            on_arc = False
            if not dx * dx + dy * dy < near:
                dist = math.hypot(dx, dy)
                on_arc = abs(dist - echo) <= half_t
                if not (on_arc or dist < free):
                    continue
            if edges and not (row >= -r0 and row < height - r0 and col >= -c0 and col < width - c0):
                continue
            flat = base + int(row) * width + int(col)
            idx[n] = flat
            sonar[n] = k
            occ[n] = on_arc
            off = lateral - half_cell
            off_axis[n] = off if off >= 0.0 or off != off else 0.0  # np.maximum(off, 0.0)
            along_kept[n] = along
            place = square[n] = (int(row) + span) * side + int(col) + span
            n += 1
            if owner[place] >= 0 and owner[place] != k:  # a cell an earlier sonar updates
                new_run = True
            owner[place] = k
        if new_run:
            runs += 1
            bounds[runs] = first
    for i in range(n):
        owner[square[i]] = -1
    runs += 1
    bounds[runs] = n
    return n, idx, sonar, occ, off_axis, along_kept, bounds, runs


@_kernel()
def elfes_weight(angle: np.ndarray, half_cone: float) -> None:
    """Elfes' angular weight ``max(0, 1 - (angle / half_cone)^2)`` in place, ``angle`` the
    ``arctan2`` of :func:`cone_cells`' ``off_axis, along`` (rad)."""
    for i in range(len(angle)):
        w = angle[i] / half_cone
        w = 1.0 - w * w
        angle[i] = w if w >= 0.0 or w != w else 0.0


@_kernel()
def arc_log_odds(flat_lo: np.ndarray, idx: np.ndarray, occ: np.ndarray, start: int,
                 stop: int) -> np.ndarray:
    """The negated log-odds of the echo arcs' cells among entries ``start:stop`` (to take
    ``exp`` of: Konolige's blame, :func:`fuse`)."""
    out = np.empty(stop - start)
    n = 0
    for i in range(start, stop):
        if occ[i]:
            out[n] = -flat_lo[idx[i]]
            n += 1
    return out[:n]


@_kernel()
def fuse(flat_lo: np.ndarray, idx: np.ndarray, sonar: np.ndarray, occ: np.ndarray,
         weight: np.ndarray, arc_exp: np.ndarray, count: int, start: int, stop: int,
         elfes: bool, l_occ: float, l_free: float, l_min: float, l_max: float,
         echo_share: float, out: np.ndarray) -> None:
    """``_fuse`` of the entries ``start:stop`` (one run: no cell twice): adds the model's
    log-odds to ``flat_lo`` (clamped to ``[l_min, l_max]``) and writes the negated new log-odds
    to ``out[start:stop]``. ``arc_exp``: ``exp`` of :func:`arc_log_odds` ("elfes"); ``weight``
    Elfes' weights (unused for "band")."""
    share = np.empty(len(arc_exp))
    total = np.zeros(count)
    if elfes:  # Konolige's share of each sonar's echo over its own arc: w_i p_i / sum_j w_j p_j
        a = 0
        for i in range(start, stop):
            if occ[i]:
                blame = weight[i] / (arc_exp[a] + 1.0)
                share[a] = blame
                total[sonar[i]] += blame
                a += 1
    a = 0
    for i in range(start, stop):
        lo = flat_lo[idx[i]]
        if not elfes:
            delta = l_occ if occ[i] else l_free
        elif occ[i]:
            t = total[sonar[i]]
            s = echo_share * share[a] / t if t > 0 else 0.0
            a += 1
            delta = (s if s <= 1.0 or s != s else 1.0) * l_occ  # np.minimum(s, 1.0)
        else:
            delta = weight[i] * l_free
        fused = lo + delta
        if not (fused >= l_min or fused != fused):
            fused = l_min
        if not (fused <= l_max or fused != fused):
            fused = l_max
        flat_lo[idx[i]] = fused
        out[i] = -fused


@_kernel()
def negated_log_odds(flat_lo: np.ndarray, idx: np.ndarray, out: np.ndarray) -> None:
    """``out[i] = -flat_lo[idx[i]]`` (the cells' final log-odds when a cell changed in two runs)."""
    for i in range(len(out)):
        out[i] = -flat_lo[idx[i]]


@_kernel()
def write_values(values: np.ndarray, idx: np.ndarray, exp_neg: np.ndarray) -> None:
    """``values[idx] = rint(100 / (1 + exp_neg))`` (uint8; ``exp_neg`` the ``exp`` of the
    negated log-odds: :func:`~nav_bench.mapping.occupancy.log_odds_to_values`)."""
    for i in range(len(exp_neg)):
        values[idx[i]] = np.uint8(np.rint(100.0 / (exp_neg[i] + 1.0)))
