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
def _forget(carved_t: np.ndarray, seen_t: np.ndarray, seen_view: np.ndarray, noted: np.ndarray,
            a0: int, b0: int, occupied_box: np.ndarray) -> None:
    """``_forget``: every noted cell of the box (``occupied_box`` (h, w) from row ``a0``, column
    ``b0``) that is not occupied forgets its records (``-inf`` times, view -1) and its note."""
    h, w = occupied_box.shape
    for i in range(h):
        for j in range(w):
            if noted[a0 + i, b0 + j] and not occupied_box[i, j]:
                carved_t[a0 + i, b0 + j, :] = -np.inf
                seen_t[a0 + i, b0 + j, :] = -np.inf
                seen_view[a0 + i, b0 + j, :] = -1
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
def _mounts(pose: np.ndarray, offsets: np.ndarray, angles: np.ndarray, ranges: np.ndarray,
            max_range: float) -> np.ndarray:
    """(6, S): each sonar's mount x, y (m), capped range (m; no echo or not finite:
    ``max_range``), axis angle (rad) and unit vector x, y: ``_Mounts.of`` and the axes of
    ``see_through_pairs`` (``pose`` = x, y, yaw, cos yaw, sin yaw as Python computes them)."""
    x, y, yaw, cy, sy = pose[0], pose[1], pose[2], pose[3], pose[4]
    out = np.empty((6, angles.shape[0]))
    for s in range(angles.shape[0]):
        out[0, s] = x + cy * offsets[s, 0] - sy * offsets[s, 1]
        out[1, s] = y + sy * offsets[s, 0] + cy * offsets[s, 1]
        out[2, s] = min(ranges[s], max_range) if math.isfinite(ranges[s]) else max_range
        out[3, s] = yaw + angles[s]
        out[4, s] = math.cos(out[3, s])
        out[5, s] = math.sin(out[3, s])
    return out


@_kernel()
def carve_cells(carved_t: np.ndarray, seen_t: np.ndarray, seen_view: np.ndarray, noted: np.ndarray,
                a0: int, b0: int, occupied_box: np.ndarray, rows: np.ndarray, cols: np.ndarray,
                offsets: np.ndarray, sonar_offsets: np.ndarray, sonar_angles: np.ndarray,
                ranges: np.ndarray, setup: np.ndarray, reading: np.ndarray, view: int,
                centres: np.ndarray, parts: np.ndarray, kept: np.ndarray, kept_xy: np.ndarray) -> int:
    """``SeeThroughCarving.update`` after the view is chosen: ``_forget`` in the box
    (``occupied_box`` from row ``a0``, column ``b0``), then, for the cells (``rows``, ``cols``
    (M,), distinct): note them, fill ``centres`` (M, 2) and ``parts`` (M, PARTS, 2) (m), update
    the records of the parts seen through (confirmed from another view within the confirmation
    limit: carved now), on an echo's axis point (kept again, when asked) or under the body (when
    asked), fill ``kept`` (M, PARTS): carved before the memory's limit, and ``kept_xy[:K]`` with
    the kept parts' centres, cell by cell; returns K.

    ``carved_t``, ``seen_t``, ``seen_view`` (H, W, PARTS), ``noted`` (H, W): the records.
    ``offsets`` (PARTS, 2): the parts' offsets from their cell's centre, m. The sonars:
    ``sonar_offsets`` (S, 2) m, ``sonar_angles`` (S,) rad, this reading's ``ranges`` (S,) m.
    ``setup`` = (grid xmin, ymin, cell, max range, cos of half the cone, half the cone, a part's
    centre-to-corner, reach: centre to the farthest part centre, the robot's radius, the reach of
    the under-the-body cell test, the axis tolerances across and along, the undo's reach), m and
    rad. ``reading`` = (x, y, yaw, cos yaw, sin yaw, t, the confirmation's limit, the memory's
    limit, 1.0 if the body carves, the undo mode: its index in ``carving.UNDO_MODES``, the time
    the body's carving is recorded at, that time as the records are compared with it), m, rad,
    s: the limits as the records are compared with them; ``view`` its view."""
    _forget(carved_t, seen_t, seen_view, noted, a0, b0, occupied_box)
    mounts = _mounts(reading, sonar_offsets, sonar_angles, ranges, setup[3])
    xmin, ymin, cell = setup[0], setup[1], setup[2]
    x, y, t, limit, keep_limit = reading[0], reading[1], reading[5], reading[6], reading[7]
    body, axis, unexplained = reading[8] > 0.0, reading[9] == 1.0, reading[9] == 2.0
    radius, under_reach = setup[8], setup[9]
    n_parts = offsets.shape[0]
    seen_all = np.zeros((rows.shape[0], n_parts), dtype=np.bool_)
    echoed = np.zeros(n_parts, dtype=np.bool_)
    for m in range(rows.shape[0]):
        r, c = rows[m], cols[m]
        cx = xmin + (float(c) + 0.5) * cell
        cy = ymin + (float(r) + 0.5) * cell
        centres[m, 0], centres[m, 1] = cx, cy
        for p in range(n_parts):
            parts[m, p, 0] = cx + offsets[p, 0]
            parts[m, p, 1] = cy + offsets[p, 1]
        noted[r, c] = True
        seen = seen_all[m]
        any_seen = _seen_parts(parts[m], cx, cy, mounts, setup, seen)
        any_echoed = _axis_parts(parts[m], mounts, setup, echoed) if axis else False
        if any_seen or any_echoed or (body and math.hypot(cx - x, cy - y) <= under_reach):
            _note_cell(carved_t[r, c], seen_t[r, c], seen_view[r, c], parts[m], seen, echoed, x, y,
                       radius if body else -1.0, view, t, limit, reading[10], reading[11])
    if unexplained:
        _undo_unexplained(carved_t, rows, cols, parts, seen_all, mounts, setup, keep_limit)
    k = 0
    for m in range(rows.shape[0]):
        r, c = rows[m], cols[m]
        for p in range(n_parts):
            kept[m, p] = carved_t[r, c, p] < keep_limit
            if kept[m, p]:
                kept_xy[k, 0], kept_xy[k, 1] = parts[m, p, 0], parts[m, p, 1]
                k += 1
    return k


@_kernel()
def _seen_parts(pts: np.ndarray, cx: float, cy: float, mounts: np.ndarray, setup: np.ndarray,
                seen: np.ndarray) -> bool:
    """Fill ``seen`` (PARTS,) with which of one cell's parts (``pts`` (PARTS, 2), centre ``cx``,
    ``cy``, m) a sonar sees through (``_Mounts.see_through_pairs``, OR over the sonars the
    pre-filter lets through); True if any. ``mounts``: :func:`_mounts`; ``setup``: as
    :func:`carve_cells` takes it."""
    cos_half, half_cone, corner, reach = setup[4], setup[5], setup[6], setup[7]
    any_seen = False
    seen[:] = False
    for s in range(mounts.shape[1]):
        mx, my, r = mounts[0, s], mounts[1, s], mounts[2, s]
        if not _may_see(cx - mx, cy - my, r, mounts[3, s], half_cone, reach, corner):
            continue
        far = r - CARVE_MARGIN
        ax, ay = mounts[4, s], mounts[5, s]
        for p in range(pts.shape[0]):
            dx = pts[p, 0] - mx
            dy = pts[p, 1] - my
            d = math.hypot(dx, dy)
            if dx * ax + dy * ay >= d * cos_half and d + corner <= far:
                seen[p] = True
                any_seen = True
    return any_seen


@_kernel()
def _axis_parts(pts: np.ndarray, mounts: np.ndarray, setup: np.ndarray, echoed: np.ndarray) -> bool:
    """Fill ``echoed`` (PARTS,) with which of one cell's parts (``pts`` (PARTS, 2), m) lie on a
    sonar's echo axis point (``carving.echo_axis_parts``: a sonar with an echo, the part within
    ``setup``'s axis tolerances of the point on the axis at the range read); True if any."""
    max_range, across_tol, along_tol = setup[3], setup[10], setup[11]
    any_echoed = False
    echoed[:] = False
    for s in range(mounts.shape[1]):
        mx, my, r = mounts[0, s], mounts[1, s], mounts[2, s]
        if not r < max_range:
            continue
        ax, ay = mounts[4, s], mounts[5, s]
        for p in range(pts.shape[0]):
            dx = pts[p, 0] - mx
            dy = pts[p, 1] - my
            if abs(dx * ay - dy * ax) <= across_tol and abs(dx * ax + dy * ay - r) <= along_tol:
                echoed[p] = True
                any_echoed = True
    return any_echoed


@_kernel()
def _on_arc(px: float, py: float, mounts: np.ndarray, s: int, cos_half: float, along_tol: float) -> bool:
    """Whether the part at (``px``, ``py``) (m) lies inside sonar ``s``'s cone within
    ``along_tol`` (m) of its range (``carving.unexplained_echo_parts``' arc test)."""
    dx = px - mounts[0, s]
    dy = py - mounts[1, s]
    d = math.hypot(dx, dy)
    return dx * mounts[4, s] + dy * mounts[5, s] >= d * cos_half and abs(d - mounts[2, s]) <= along_tol


@_kernel()
def _undo_unexplained(carved_t: np.ndarray, rows: np.ndarray, cols: np.ndarray, parts: np.ndarray,
                      seen_all: np.ndarray, mounts: np.ndarray, setup: np.ndarray, keep_limit: float) -> None:
    """``carving.unexplained_echo_parts`` and its undo: for each sonar with an echo up to the
    undo's reach whose arc holds parts of the cells (``rows``, ``cols``; ``parts`` (M, PARTS, 2)
    m) but no kept one (carved before ``keep_limit``, s), every part on the arc not seen through
    this reading (``seen_all`` (M, PARTS)) is kept again (``-inf``). Every sonar is judged on
    the records before any undo."""
    max_range, cos_half, along_tol, reach = setup[3], setup[4], setup[11], setup[12]
    n_sonars = mounts.shape[1]
    unexplained = np.zeros(n_sonars, dtype=np.bool_)
    for s in range(n_sonars):
        r = mounts[2, s]
        if not (r < max_range and r <= reach):
            continue
        on_any, explained = False, False
        for m in range(rows.shape[0]):
            for p in range(parts.shape[1]):
                if _on_arc(parts[m, p, 0], parts[m, p, 1], mounts, s, cos_half, along_tol):
                    on_any = True
                    if carved_t[rows[m], cols[m], p] < keep_limit:
                        explained = True
        unexplained[s] = on_any and not explained
    for s in range(n_sonars):
        if not unexplained[s]:
            continue
        for m in range(rows.shape[0]):
            for p in range(parts.shape[1]):
                if not seen_all[m, p] and _on_arc(parts[m, p, 0], parts[m, p, 1], mounts, s, cos_half, along_tol):
                    carved_t[rows[m], cols[m], p] = -np.inf


@_kernel()
def _note_cell(carved: np.ndarray, seen_at: np.ndarray, views: np.ndarray, pts: np.ndarray,
               seen: np.ndarray, echoed: np.ndarray, x: float, y: float, radius: float, view: int,
               t: float, limit: float, body_t: float, body_cmp: float) -> None:
    """``_note`` for one cell's records (PARTS,): a part seen through is carved if a reading from
    another view saw through it since ``limit``; it is then seen at ``t`` from ``view``; a part
    on an echo's axis point (``echoed``) and not seen through is kept again (``-inf``); a part
    within ``radius`` of the body's centre (``x``, ``y``) is carved at ``body_t`` if its record
    is earlier (compared with ``body_cmp``) (``x``, ``y``, ``radius`` m, negative: no body
    carving; ``t``, ``limit``, ``body_t``, ``body_cmp`` s)."""
    for p in range(carved.shape[0]):
        if seen[p]:
            if views[p] >= 0 and views[p] != view and seen_at[p] >= limit:
                carved[p] = t
            seen_at[p] = t
            views[p] = view
        elif echoed[p]:
            carved[p] = -np.inf
        if math.hypot(pts[p, 0] - x, pts[p, 1] - y) <= radius and carved[p] < body_cmp:
            carved[p] = body_t


# -- the clearance against the kept parts (footprint.PointObstacles) -----------------------------
@_kernel()
def nearest_one(x: float, y: float, centres: np.ndarray) -> float:
    """The least ``dx * dx + dy * dy`` (m^2) from (``x``, ``y``) to ``centres`` (K, 2), K > 0:
    ``PointObstacles._one``'s sum and minimum."""
    best = np.inf
    for i in range(centres.shape[0]):
        dx, dy = x - centres[i, 0], y - centres[i, 1]
        d2 = dx * dx + dy * dy
        if d2 < best:
            best = d2
    return best


@_kernel()
def nearest(xy: np.ndarray, centres: np.ndarray, bound: float, box: np.ndarray) -> np.ndarray:
    """(N,) distance (m) from each point ``xy`` (N, 2) to the nearest of ``centres`` (K, 2),
    ``inf`` at ``bound`` and beyond: ``PointObstacles._nearest``'s direct path (only centres
    within ``bound`` + 1e-9 along x and y of the points' ``box`` = (x min, y min, x max, y max)
    are looked at; the squared distances compared with ``bound`` squared)."""
    reach = bound + 1e-9
    lo_x, lo_y, hi_x, hi_y = box[0] - reach, box[1] - reach, box[2] + reach, box[3] + reach
    limit = bound * bound
    out = np.empty(xy.shape[0])
    out[:] = np.inf
    for i in range(centres.shape[0]):
        cx, cy = centres[i, 0], centres[i, 1]
        if not (cx >= lo_x and cx <= hi_x and cy >= lo_y and cy <= hi_y):
            continue
        for j in range(xy.shape[0]):
            dx, dy = xy[j, 0] - cx, xy[j, 1] - cy
            d2 = dx * dx + dy * dy
            if d2 < out[j]:
                out[j] = d2
    for j in range(xy.shape[0]):
        out[j] = math.sqrt(out[j]) if out[j] < limit else np.inf
    return out
