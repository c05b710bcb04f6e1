"""The see-through carving's compiled kernel (Numba, the optional ``fast`` extra) against the
NumPy code: the same records (carved and seen times, views, notes), centres, parts and kept
masks, bit for bit, over long random sequences of poses, readings with and without echoes,
cells occupied, freed and re-occupied, views changing and memory expiring. Skipped without
Numba."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.errors import InputError
from nav_bench.interface import Observation
from nav_bench.mapping.grid import GridFrame
from nav_bench.planners import carving as carving_mod
from nav_bench.planners.carving import SeeThroughCarving, load_kernels
from nav_bench.testing.harness import default_robot

needs_numba = pytest.mark.skipif(load_kernels() is None, reason="numba is not installed (the 'fast' extra)")


def assert_same(a: SeeThroughCarving, b: SeeThroughCarving, out_a: object, out_b: object) -> None:
    """Records, notes, views and the returned cells equal bit for bit."""
    for name in ("carved_t", "seen_t", "seen_view", "noted"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert (a.view, a.view_pose) == (b.view, b.view_pose)
    for name in ("centres", "parts", "kept"):
        x, y = getattr(out_a, name), getattr(out_b, name)
        assert x.dtype == y.dtype and x.shape == y.shape and np.array_equal(x, y), name
    assert np.array_equal(out_a.kept_parts(), out_b.kept_parts())  # type: ignore[attr-defined]


def random_ranges(rng: np.random.Generator, n: int, max_range: float) -> np.ndarray:
    """Echoes near and far, no echo (``max_range`` or inf), now and then below the minimum."""
    ranges = rng.uniform(0.05, max_range, n)
    ranges[rng.random(n) < 0.25] = max_range
    ranges[rng.random(n) < 0.15] = np.inf
    ranges[rng.random(n) < 0.05] = 0.01
    return ranges


# (memory_s, undo, body_clear, body_memory_s): main's carving, and VFH+'s other settings
SETTINGS = [(3.0, "off", 0.0, None), (10.0, "axis", 0.0, None), (10.0, "off", 0.3, 3.0), (7.5, "axis", 0.4, None),
            (10.0, "unexplained", 0.0, None), (10.0, "unexplained", 0.3, 2.5), (10.0, "unexplained", 0.0, 3.0)]


@needs_numba
@pytest.mark.parametrize("settings", SETTINGS)
@pytest.mark.parametrize("seed", range(6))
def test_the_compiled_carving_is_the_numpy_carving_bit_for_bit(seed: int, settings: tuple) -> None:
    rng = np.random.default_rng(1500 + seed)
    robot = default_robot(radius=float(rng.uniform(0.15, 0.25)))
    cell = float(rng.choice([0.1, 0.05, 0.08]))
    frame = GridFrame(float(rng.uniform(-2.0, 0.0)), float(rng.uniform(-2.0, 0.0)), cell, 50, 60)
    pose = np.array([frame.xmin + 30 * cell, frame.ymin + 25 * cell, 0.0])
    memory_s, undo, clear, body_s = settings
    kw = {"memory_s": memory_s, "undo": undo, "body_clear": clear, "body_memory_s": body_s}
    ref, fast = SeeThroughCarving(frame, pose, "numpy", **kw), SeeThroughCarving(frame, pose, "numba", **kw)
    assert not ref.compiled and fast.compiled
    occupied = rng.random(frame.shape) < 0.2
    t, carved_seen, undone = 0.0, 0, 0
    for step in range(400):
        # the robot walks and turns, sometimes stands (the same view), sometimes jumps
        pose = pose + np.array([*rng.normal(0.0, 0.02, 2), rng.normal(0.0, 0.06)])
        if rng.random() < 0.2:
            pose = pose.copy()
            pose[:2] = [frame.xmin + rng.uniform(-0.5, 60.5) * cell, frame.ymin + rng.uniform(-0.5, 50.5) * cell]
        t = t + float(rng.choice([0.1, 0.1, 0.1, 0.7, 3.0, 2.9999999]))
        when = np.float64(t) if step % 5 == 0 else t  # a NumPy float compares in float64
        flip = rng.random(frame.shape) < 0.03  # cells freed and re-occupied
        occupied ^= flip
        r0, c0 = frame.cell_of(float(pose[0]), float(pose[1]))
        n = int(rng.integers(0, 15))
        a0, a1 = max(r0 - n, 0), min(r0 + n + 1, frame.rows)
        b0, b1 = max(c0 - n, 0), min(c0 + n + 1, frame.cols)
        a1, b1 = max(a1, a0), max(b1, b0)
        box = occupied[a0:a1, b0:b1]  # strided (D* Lite's) or a copy (VFH+'s)
        box = box.copy() if step % 2 else box
        rr, cc = np.nonzero(box)
        keep = rng.random(len(rr)) < 0.9  # a caller may look at only some of the box's cells
        rows, cols = rr[keep] + a0, cc[keep] + b0
        obs = Observation(t=when, pose=pose.copy(), goal=np.zeros(2),
                          ranges=random_ranges(rng, 6, robot.sonar.max_range), robot=robot,
                          bounds=(0.0, 0.0, 1.0, 1.0), dt=0.1)
        carved_before = np.isfinite(ref.carved_t)
        out_ref = ref.update(obs, rows, cols, (a0, a1, b0, b1), box)
        # kept again in a cell still noted: an echo's axis point, not a cell the grid freed
        undone += int((carved_before & ~np.isfinite(ref.carved_t) & ref.noted[..., None]).sum())
        out_fast = fast.update(obs, rows, cols, (a0, a1, b0, b1), box)
        assert_same(ref, fast, out_ref, out_fast)
        carved_seen += int((~out_ref.kept).sum())
    assert carved_seen > 1000  # plenty of parts carved (seen from two views, or under the body)
    if undo != "off":
        assert undone > 5  # parts an echo's axis point kept again
    else:
        assert undone == 0
    assert np.isfinite(ref.seen_t).any() and (ref.seen_view >= 0).any()


def test_the_kernel_choice_is_checked() -> None:
    frame = GridFrame(0.0, 0.0, 0.1, 4, 4)
    with pytest.raises(InputError, match="carving kernel"):
        SeeThroughCarving(frame, np.zeros(3), "fortran")
    assert not SeeThroughCarving(frame, np.zeros(3), "numpy").compiled
    assert SeeThroughCarving(frame, np.zeros(3)).compiled == (load_kernels() is not None)


def test_numba_without_numba_names_the_fast_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(carving_mod, "load_kernels", lambda: None)
    frame = GridFrame(0.0, 0.0, 0.1, 4, 4)
    with pytest.raises(InputError, match=r"nav-bench\[fast\]"):
        SeeThroughCarving(frame, np.zeros(3), "numba")
    assert not SeeThroughCarving(frame, np.zeros(3), "auto").compiled  # falls back to NumPy
    from nav_bench.planners import footprint

    monkeypatch.setattr(footprint, "load_carving_kernels", lambda: None)
    with pytest.raises(InputError, match=r"nav-bench\[fast\]"):
        footprint.PointObstacles(np.zeros((1, 2)), 0.01, 0.5, (0.0, 0.0, 1.0, 1.0), compiled=True)


def test_the_expiry_limit_is_compared_as_numpy_compares_it() -> None:
    """A Python float is rounded to float32 (NEP 50), a NumPy float64 is not."""
    records = np.array([1.0], dtype=np.float32)
    for limit in (1.00000001, np.float64(1.00000001), 0.99999999, 3.0 - 1e-12):
        as_numpy = bool((records >= limit)[0])
        assert (float(records[0]) >= carving_mod._as_compared(limit)) == as_numpy
    assert math.isinf(carving_mod._as_compared(-math.inf))


@needs_numba
def test_the_compiled_clearance_against_the_kept_parts_is_the_numpy_one_bit_for_bit() -> None:
    """PointObstacles' direct distances (one point, and rollouts of many) by the kernels: the
    same values, over random squares, points near and far, inside and outside the bounds."""
    from nav_bench.planners.footprint import PointObstacles

    rng = np.random.default_rng(1520)
    bounds = (0.0, 0.0, 4.0, 3.0)
    capped = 0
    for _ in range(600):
        centres = rng.uniform(-0.2, 4.2, (int(rng.integers(0, 400)), 2))
        if rng.random() < 0.3:  # the kept parts as the kernel hands them: a slice of a larger buffer
            centres = np.concatenate([centres, np.zeros((5, 2))])[: len(centres)]
        cap, half = float(rng.uniform(0.05, 1.0)), float(rng.choice([0.01, 0.004]))
        ref = PointObstacles(centres, half, cap, bounds)
        fast = PointObstacles(centres, half, cap, bounds, compiled=True)
        start = rng.uniform(-0.3, 4.3, 2)
        for n in (1, 2, int(rng.integers(3, 60))):
            xy = start + np.cumsum(rng.normal(0.0, 0.03, (n, 2)), axis=0)
            a, b = ref(xy), fast(xy)
            assert a.dtype == b.dtype and np.array_equal(a, b)
            capped += int((a == cap).sum())
    assert capped > 100
