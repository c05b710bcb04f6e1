"""VFH+'s compiled window reads (Numba, the optional ``fast`` extra) against the NumPy code:
the same active windows and carved windows, bit for bit, over random maps, positions, radii
and kept masks. Skipped without Numba."""

from __future__ import annotations

import numpy as np
import pytest

from nav_bench.mapping.grid import GridFrame
from nav_bench.planners.vfh_plus import ActiveWindow, load_kernels, read_window, window_box

needs_numba = pytest.mark.skipif(load_kernels() is None, reason="numba is not installed (the 'fast' extra)")

FIELDS = ("x", "y", "certainty", "dx", "dy", "dist", "rows", "cols", "weight", "area")


def assert_same_window(a: ActiveWindow, b: ActiveWindow) -> None:
    for name in FIELDS:
        u, v = getattr(a, name), getattr(b, name)
        if u is None or v is None:
            assert u is None and v is None, name
            continue
        assert u.dtype == v.dtype and u.shape == v.shape and np.array_equal(u, v), name


@needs_numba
@pytest.mark.parametrize("seed", range(4))
def test_the_compiled_window_reads_are_the_numpy_ones_bit_for_bit(seed: int) -> None:
    rng = np.random.default_rng(1510 + seed)
    frame = GridFrame(float(rng.uniform(-3.0, 1.0)), float(rng.uniform(-3.0, 1.0)), float(rng.choice([0.1, 0.05])),
                      60, 70)
    values = rng.choice(np.array([0, 20, 50, 50, 51, 60, 75, 99, 100], dtype=np.uint8), size=frame.shape)
    values.flags.writeable = False  # as the live map is read
    carved_points = 0
    for _ in range(300):
        xy = np.array([frame.xmin + rng.uniform(-5.0, 75.0) * frame.cell,
                       frame.ymin + rng.uniform(-5.0, 65.0) * frame.cell])
        radius = float(rng.uniform(0.0, 2.0))
        c_max = float(rng.choice([1.0, 15.0, 0.3]))
        box = window_box(frame, xy, radius)
        ref = read_window(values, frame, xy, radius, c_max, box)
        fast = read_window(values, frame, xy, radius, c_max, box, compiled=True)
        assert_same_window(ref, fast)
        parts = ref.x[:, None, None] + rng.normal(0.0, frame.cell / 3, (len(ref), 25, 2))
        kept = rng.random((len(ref), 25)) < float(rng.choice([0.3, 0.9, 0.99, 1.0]))
        kept[rng.random(len(ref)) < 0.5] = True  # whole cells among carved ones
        a = ref.carved(kept, parts, xy)
        b = fast.carved(kept, parts, xy, compiled=True)
        assert (a is ref) == (b is fast)
        assert_same_window(a, b)
        carved_points += int(a.weight is not None and (a.weight < 1.0).sum())
    assert carved_points > 1000
