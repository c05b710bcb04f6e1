""":class:`~nav_bench.planners.carving.SeeThroughCarving`'s per-cell and per-part work compiled
with Numba (the optional ``fast`` extra: ``pip install nav-bench[fast]``).

:func:`carve_cells` is ``SeeThroughCarving.update`` after the view is chosen: ``_forget``, the
cell centres and parts, :func:`~nav_bench.planners.footprint.seen_through_cells` (its cell
pre-filter, then the part test of each cell against the sonars that passed it), the
under-the-body test, the record updates of ``_note`` and the ``kept`` mask, in loops, the same
IEEE operations in the same order as the NumPy code (no fast-math: no fused multiply-add;
``hypot``, ``sqrt``, ``sin``, ``cos`` are NumPy's bit for bit here). The pre-filter's
``atan2`` and ``asin`` may differ from NumPy's in the last bit, but the pre-filter is
conservative by 1e-6 rad (m): it only skips cells whose parts the part test would all reject,
so the records and masks are the same bit for bit either way.

The times: records are float32, the reading's time a float. NumPy compares a float32 array with
a Python float in float32 (the float rounded, NEP 50) and with a NumPy float64 in float64: the
caller passes the expiry limit already rounded as NumPy would compare it (a float32 value
compared in float64 gives the float32 comparison exactly), and a time stored into a float32
record is rounded to nearest, as NumPy's assignment does.

Imported only when a carving chooses the kernel (:func:`nav_bench.compiled.load`), compiled and
cached by :func:`nav_bench.compiled.kernel`.
"""

from __future__ import annotations

import math

import numpy as np

from nav_bench.compiled import kernel as _kernel
from nav_bench.planners.footprint import CARVE_MARGIN

TWO_PI = 2 * math.pi


@_kernel()
def forget(carved_t: np.ndarray, seen_t: np.ndarray, seen_view: np.ndarray, noted: np.ndarray,
           a0: int, b0: int, occupied_box: np.ndarray) -> None:
    """``_forget``: every noted cell of the box (``occupied_box`` (h, w) from row ``a0``, column
    ``b0``) that is not occupied forgets its records (``-inf`` times, view -1) and its note.
    ``carved_t``, ``seen_t``, ``seen_view``: (H * W, PARTS) rows by flat cell."""
    h, w = occupied_box.shape
    cols = noted.shape[1]
    parts = carved_t.shape[1]
    for i in range(h):
        for j in range(w):
            if noted[a0 + i, b0 + j] and not occupied_box[i, j]:
                f = (a0 + i) * cols + b0 + j
                for p in range(parts):
                    carved_t[f, p] = -np.inf
                    seen_t[f, p] = -np.inf
                    seen_view[f, p] = -1
                noted[a0 + i, b0 + j] = False


@_kernel()
def _may_see(dx: float, dy: float, r: float, axis: float, half_cone: float, reach: float,
             corner: float) -> bool:
    """``seen_through_cells``' pre-filter for one cell (centre ``dx``, ``dy`` m from the mount)
    and one sonar (range ``r`` m, axis ``axis`` rad): may one of the cell's parts lie nearer than
    the range and inside the cone? ``reach``: centre to the farthest part centre, ``corner``:
    part centre to its corner, m. Loosened by 1e-6 (m, rad): the part test decides."""
    d = math.hypot(dx, dy)
    if not (d - reach + corner <= r - CARVE_MARGIN + 1e-6):
        return False
    if d <= reach:
        return True
    ang = abs(math.atan2(dy, dx) - axis) % TWO_PI
    ang = min(ang, TWO_PI - ang)  # off the axis, [0, pi]
    spread = math.asin(min(reach / max(d, 1e-12), 1.0))
    return ang <= half_cone + spread + 1e-6


@_kernel()
def carve_cells(carved_t: np.ndarray, seen_t: np.ndarray, seen_view: np.ndarray, noted: np.ndarray,
                rows: np.ndarray, cols: np.ndarray, xmin: float, ymin: float, cell: float,
                offsets: np.ndarray, mx: np.ndarray, my: np.ndarray, r: np.ndarray, ax: np.ndarray,
                ay: np.ndarray, axis: np.ndarray, sonar_geom: np.ndarray, body: np.ndarray,
                view: int, t: float, limit: float, centres: np.ndarray, parts: np.ndarray,
                kept: np.ndarray) -> None:
    """``SeeThroughCarving.update`` for the cells (``rows``, ``cols`` (M,), distinct), after
    ``forget``: note them, fill ``centres`` (M, 2) and ``parts`` (M, PARTS, 2) (m), update the
    records of the parts seen through (confirmed from another view within the memory: carved at
    ``t``) or under the body, and fill ``kept`` (M, PARTS): carved before ``limit`` (s).

    The reading: mounts ``mx``, ``my`` (m), capped ranges ``r`` (m), axis unit vectors ``ax``,
    ``ay`` and world angles ``axis`` (rad), (S,) each; ``sonar_geom`` = (cos of half the cone,
    half the cone (rad), part's centre-to-corner (m), reach (m): centre to the farthest part
    centre); ``body`` = (x, y, radius, reach of the under-the-body cell test), m. ``offsets``
    (PARTS, 2): the parts' offsets from their cell's centre, m."""
    n_parts = offsets.shape[0]
    grid_cols = noted.shape[1]
    cos_half, half_cone, corner, reach = sonar_geom[0], sonar_geom[1], sonar_geom[2], sonar_geom[3]
    x, y, radius, under_reach = body[0], body[1], body[2], body[3]
    seen = np.zeros(n_parts, dtype=np.bool_)
    for m in range(rows.shape[0]):
        f = rows[m] * grid_cols + cols[m]
        noted[rows[m], cols[m]] = True
        cx = xmin + (float(cols[m]) + 0.5) * cell
        cy = ymin + (float(rows[m]) + 0.5) * cell
        centres[m, 0], centres[m, 1] = cx, cy
        for p in range(n_parts):
            parts[m, p, 0] = cx + offsets[p, 0]
            parts[m, p, 1] = cy + offsets[p, 1]
        any_seen = _seen_parts(parts[m], cx, cy, mx, my, r, ax, ay, axis, cos_half, half_cone, corner,
                               reach, seen)
        if any_seen or math.hypot(cx - x, cy - y) <= under_reach:
            _note_cell(carved_t[f], seen_t[f], seen_view[f], parts[m], seen, x, y, radius, view, t, limit)
        for p in range(n_parts):
            kept[m, p] = carved_t[f, p] < limit


@_kernel()
def _seen_parts(pts: np.ndarray, cx: float, cy: float, mx: np.ndarray, my: np.ndarray, r: np.ndarray,
                ax: np.ndarray, ay: np.ndarray, axis: np.ndarray, cos_half: float, half_cone: float,
                corner: float, reach: float, seen: np.ndarray) -> bool:
    """Fill ``seen`` (PARTS,) with which of one cell's parts (``pts`` (PARTS, 2), centre ``cx``,
    ``cy``, m) a sonar sees through (``_Mounts.see_through_pairs``, OR over the sonars the
    pre-filter lets through); True if any."""
    any_seen = False
    seen[:] = False
    for s in range(mx.shape[0]):
        if not _may_see(cx - mx[s], cy - my[s], r[s], axis[s], half_cone, reach, corner):
            continue
        far = r[s] - CARVE_MARGIN
        for p in range(pts.shape[0]):
            dx = pts[p, 0] - mx[s]
            dy = pts[p, 1] - my[s]
            d = math.hypot(dx, dy)
            if dx * ax[s] + dy * ay[s] >= d * cos_half and d + corner <= far:
                seen[p] = True
                any_seen = True
    return any_seen


@_kernel()
def _note_cell(carved: np.ndarray, seen_at: np.ndarray, views: np.ndarray, pts: np.ndarray,
               seen: np.ndarray, x: float, y: float, radius: float, view: int, t: float,
               limit: float) -> None:
    """``_note`` for one cell's records (PARTS,): a part seen through is carved if a reading from
    another view saw through it since ``limit``; it is then seen at ``t`` from ``view``; a part
    within ``radius`` of the body's centre (``x``, ``y``) is carved. Times in m and s."""
    for p in range(carved.shape[0]):
        if seen[p]:
            if views[p] >= 0 and views[p] != view and seen_at[p] >= limit:
                carved[p] = t
            seen_at[p] = t
            views[p] = view
        if math.hypot(pts[p, 0] - x, pts[p, 1] - y) <= radius:
            carved[p] = t
