"""Rasters of the true geometry: cell layout, occupancy, inflation, distance field."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data
from nav_bench.world.raster import grid_shape, rasterize


def make_world(obstacles=(), size=(10.0, 10.0), boundary=False):
    return world_from_data({"size": list(size), "boundary": boundary, "start": [0.5, 0.5],
                            "goal": [size[0] - 0.5, size[1] - 0.5], "obstacles": list(obstacles)})


def test_grid_layout_row_zero_at_the_bottom():
    raster = rasterize(static_geometry(make_world()), 0.05)
    assert raster.shape == (200, 200)
    assert raster.origin == (0.0, 0.0)
    assert raster.bounds == pytest.approx((0.0, 0.0, 10.0, 10.0))
    assert not raster.occupied.any()
    assert raster.world_to_cell((0.07, 9.99)).tolist() == [199, 1]
    assert raster.cell_center(0, 1).tolist() == pytest.approx([0.075, 0.025])
    rc = np.array([[3, 7], [150, 12]])
    assert raster.world_to_cell(raster.cell_center(rc[:, 0], rc[:, 1])).tolist() == rc.tolist()


def test_grid_shape_keeps_whole_cells_and_counts_partial_ones():
    assert grid_shape((0, 0, 10.0, 3.0), 0.05) == (60, 200)
    assert grid_shape((0, 0, 1.02, 1.0), 0.05) == (20, 21)


def test_axis_aligned_box_occupies_exactly_its_cells():
    world = make_world([{"box": {"center": [5.0, 5.0], "size": [1.0, 0.5]}}])
    raster = rasterize(static_geometry(world), 0.05)
    # centres 4.525..5.475 (20 columns) x 4.775..5.225 (10 rows)
    assert raster.occupied.sum() == 200
    rows, cols = np.nonzero(raster.occupied)
    assert (rows.min(), rows.max(), cols.min(), cols.max()) == (95, 104, 90, 109)


def test_inflated_cylinder_area_matches_the_disc():
    world = make_world([{"cylinder": {"center": [5.0, 5.0], "radius": 0.5}}])
    raster = rasterize(static_geometry(world), 0.02, inflate=0.25)
    area = raster.occupied.sum() * 0.02**2
    assert area == pytest.approx(math.pi * 0.75**2, rel=0.01)


def test_boundary_walls_inflate_inwards():
    raster = rasterize(static_geometry(make_world(boundary=True)), 0.05, inflate=0.2)
    # row centres 0.025 .. 0.175 lie within 0.2 m of the bottom wall, 0.225 does not
    assert raster.occupied[:4, 100].all()
    assert not raster.occupied[4, 100]
    assert raster.occupied[100, :4].all() and raster.occupied[100, -4:].all()
    assert not raster.occupied[4:-4, 4:-4].any()


def test_cells_outside_the_world_are_occupied():
    raster = rasterize(static_geometry(make_world(size=(2.0, 1.0))), 0.1, bounds=(-0.5, -0.5, 3.0, 1.5))
    assert raster.shape == (20, 35)
    assert raster.origin == (-0.5, -0.5)
    inside = raster.is_free(raster.cell_center(*np.mgrid[0:20, 0:35]))
    centres = raster.cell_center(*np.mgrid[0:20, 0:35])
    in_world = ((centres[..., 0] > 0) & (centres[..., 0] < 2) & (centres[..., 1] > 0) & (centres[..., 1] < 1))
    assert np.array_equal(inside, in_world)


def test_windowed_rasterisation_equals_all_pairs_clearance():
    rng = np.random.default_rng(3)
    obstacles = [{"box": {"center": rng.uniform(1, 9, 2).tolist(), "size": rng.uniform(0.1, 1.5, 2).tolist(),
                          "yaw_deg": float(rng.uniform(0, 180))}} for _ in range(25)]
    obstacles += [{"cylinder": {"center": rng.uniform(1, 9, 2).tolist(), "radius": float(rng.uniform(0.05, 0.6))}}
                  for _ in range(25)]
    obstacles += [{"wall": {"from": [1.0, 1.0], "to": [8.0, 6.0], "thickness": 0.1}}]
    world = make_world(obstacles, boundary=True)
    geometry = static_geometry(world)
    raster = rasterize(geometry, 0.05, inflate=0.18, chunk_cells=4096)
    centres = raster.cell_center(*np.mgrid[0:200, 0:200]).reshape(-1, 2)
    expected = (clearance(geometry, centres) <= 0.18).reshape(200, 200)
    assert np.array_equal(raster.occupied, expected)


def test_distance_field_in_metres():
    world = make_world([{"box": {"center": [0.55, 0.55], "size": [0.1, 0.1]}}], size=(2.0, 2.0))
    raster = rasterize(static_geometry(world), 0.1)
    assert raster.occupied.sum() == 1 and raster.occupied[5, 5]
    field = raster.distance_field()
    assert field[5, 5] == 0.0
    assert field[5, 8] == pytest.approx(0.3)
    assert field[9, 9] == pytest.approx(0.4 * math.sqrt(2))
    assert np.isinf(rasterize(static_geometry(make_world()), 0.5).distance_field()).all()


def test_rejects_non_positive_resolution():
    with pytest.raises(ValueError, match="resolution"):
        rasterize(static_geometry(make_world()), 0.0)
