"""VFH+'s active-window reads compiled with Numba (the optional ``fast`` extra: ``pip install
nav-bench[fast]``): :func:`window_cells` is :func:`nav_bench.planners.vfh_plus.read_window`'s
cell loop and :func:`carved_points` is :meth:`nav_bench.planners.vfh_plus.ActiveWindow.carved`,
in loops, the same IEEE operations in the same order (no fast-math; ``hypot`` is NumPy's bit for
bit here), so the windows are the NumPy code's bit for bit (tests/planners/test_vfh_kernels.py).

Imported only when a planner chooses the kernels (:func:`nav_bench.compiled.load`), compiled and
cached by :func:`nav_bench.compiled.kernel`.
"""

from __future__ import annotations

import math

import numpy as np

from nav_bench.compiled import kernel as _kernel


@_kernel()
def window_cells(values: np.ndarray, box: np.ndarray, xs: np.ndarray, ys: np.ndarray, x: float,
                 y: float, radius: float, c_max: float, unknown: int) -> tuple[np.ndarray, ...]:
    """The cells of ``values`` (H, W) 0..100 in ``box`` = (row0, row1, col0, col1) above
    ``unknown`` whose centre (``xs`` (W,) of the columns, ``ys`` (H,) of the rows, m) lies within
    ``radius`` m of (``x``, ``y``), row-major: (rows, cols, centre x, centre y, certainty
    ``min((v - 50) / 50, 1) c_max``, dx, dy, distance), each (M,)."""
    rs, re, cs, ce = box[0], box[1], box[2], box[3]
    n = (re - rs) * (ce - cs)
    rows, cols = np.empty(n, dtype=np.intp), np.empty(n, dtype=np.intp)
    cx, cy, cert = np.empty(n), np.empty(n), np.empty(n)
    dx, dy, dist = np.empty(n), np.empty(n), np.empty(n)
    m = 0
    for r in range(rs, re):
        for c in range(cs, ce):
            v = values[r, c]
            if v <= unknown:
                continue
            ex, ey = xs[c] - x, ys[r] - y
            d = math.hypot(ex, ey)
            if not d <= radius:
                continue
            rows[m], cols[m], cx[m], cy[m] = r, c, xs[c], ys[r]
            cert[m] = min((float(v) - 50.0) / 50.0, 1.0) * c_max
            dx[m], dy[m], dist[m] = ex, ey, d
            m += 1
    return rows[:m], cols[:m], cx[:m], cy[:m], cert[:m], dx[:m], dy[:m], dist[:m]


@_kernel()
def carved_points(x: np.ndarray, y: np.ndarray, certainty: np.ndarray, kept: np.ndarray,
                  parts: np.ndarray, x0: float, y0: float) -> tuple[np.ndarray, ...]:
    """Each window cell (centre ``x``, ``y`` (M,) m, ``certainty`` (M,)) with every part kept
    (``kept`` (M, P) bool) as its centre, weight and area 1; each other cell as its kept parts
    (``parts`` (M, P, 2) m), weight ``1 / k`` (k its kept parts) and area ``1 / P``, in window
    order: (x, y, certainty, weight, area, dx, dy, distance from (``x0``, ``y0``)), each (N,)."""
    m_cells, n_parts = kept.shape
    n = m_cells * n_parts
    px, py, cert, weight, area = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    k = 0
    for m in range(m_cells):
        count = 0
        for p in range(n_parts):
            if kept[m, p]:
                count += 1
        if count == n_parts:
            px[k], py[k], cert[k], weight[k], area[k] = x[m], y[m], certainty[m], 1.0, 1.0
            k += 1
            continue
        share = 1.0 / max(count, 1)
        for p in range(n_parts):
            if kept[m, p]:
                px[k], py[k], cert[k], weight[k] = parts[m, p, 0], parts[m, p, 1], certainty[m], share
                area[k] = 1.0 / n_parts
                k += 1
    dx, dy, dist = np.empty(k), np.empty(k), np.empty(k)
    for i in range(k):
        dx[i], dy[i] = px[i] - x0, py[i] - y0
        dist[i] = math.hypot(dx[i], dy[i])
    return px[:k], py[:k], cert[:k], weight[:k], area[:k], dx, dy, dist
