"""Cover the occupied cells of a grid with few axis-aligned rectangles (exactly, no overlap).

Imported grid maps have thousands of occupied cells; one box per cell would make the
physics scene and every geometric query slow. :func:`merge_cells` partitions them greedily.
"""

from __future__ import annotations

import numpy as np

Rect = tuple[int, int, int, int]  # row0, col0, rows, cols (cells)


def _run_length(row: np.ndarray, start: int) -> int:
    """Number of consecutive True values of a 1-D bool array from ``start``."""
    stop = np.flatnonzero(~row[start:])
    return int(stop[0]) if len(stop) else len(row) - start


def merge_cells(occupied: np.ndarray) -> list[Rect]:
    """Partition the True cells of a (H, W) bool grid into rectangles.

    Greedy, in row-major order: at the first cell not yet covered, grow a rectangle
    right-then-down (widest run, then as many rows as the whole run stays uncovered and
    occupied) and down-then-right (tallest column, then as many columns as fit), and keep
    the larger of the two. The union of the rectangles is exactly the occupied set and no
    two rectangles share a cell.

    Returns:
        list of ``(row0, col0, rows, cols)`` in cells.
    """
    todo = np.array(occupied, dtype=bool, copy=True)
    h, w = todo.shape
    rects: list[Rect] = []
    flat = todo.ravel()  # a view: clearing ``todo`` updates it
    pos = 0
    while True:
        nxt = np.flatnonzero(flat[pos:])
        if not len(nxt):
            break
        idx = pos + int(nxt[0])
        r, c = divmod(idx, w)
        # right then down
        width = _run_length(todo[r], c)
        rows_a = 1
        while r + rows_a < h and todo[r + rows_a, c:c + width].all():
            rows_a += 1
        # down then right
        height = _run_length(todo[:, c], r)
        cols_b = 1
        while c + cols_b < w and todo[r:r + height, c + cols_b].all():
            cols_b += 1
        rect = (r, c, rows_a, width) if rows_a * width >= height * cols_b else (r, c, height, cols_b)
        todo[rect[0]:rect[0] + rect[2], rect[1]:rect[1] + rect[3]] = False
        rects.append(rect)
        pos = idx  # everything before idx is already covered
    return rects


def rects_to_mask(rects: list[Rect], shape: tuple[int, int]) -> np.ndarray:
    """(H, W) int array counting how many rectangles cover each cell (for checks)."""
    count = np.zeros(shape, dtype=int)
    for r, c, nr, nc in rects:
        count[r:r + nr, c:c + nc] += 1
    return count
