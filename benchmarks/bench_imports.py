"""Map importers and optimal paths: fidelity and speed figures.

    python benchmarks/bench_imports.py [--maps DIR]

Prints:
1. grid search speed (400 x 400 grid, scipy csgraph Dijkstra);
2. every MovingAI ``.scen`` line reproduced by ``grid_path_length`` on the *imported* world
   (boxes rasterised back at the cell size): max relative error over all lines;
3. the disc robot's optimal path (radius 0.18 m, raster 0.05 m) on the imported world
   (cell 0.5 m) against the scaled ``.scen`` optimum (x 0.5 m): ratio median / min / max;
4. importer speed and shape counts (TurtleBot3, LSE arena, BARN).

DIR defaults to ``../shared/maps`` beside the repository, else ``tests/data/maps``.
"""

from __future__ import annotations

import argparse
import gzip
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

from nav_bench.world.geometry import static_geometry
from nav_bench.world.imports import import_barn, import_movingai, import_ros, read_scen
from nav_bench.world.load import world_from_data
from nav_bench.world.optimal import (
    grid_distances,
    grid_graph,
    grid_path,
    optimal_path,
    raster_optimal_path,
)
from nav_bench.world.raster import rasterize

REPO = Path(__file__).resolve().parents[1]
ROBOT_RADIUS = 0.18
CELL = 0.5


def find_maps(arg: str | None) -> Path:
    if arg:
        return Path(arg)
    shared = REPO.parent / "shared" / "maps"
    if shared.is_dir():
        return shared
    # the test copies keep two files gzipped: unpack them into a temporary folder
    tmp = Path(tempfile.mkdtemp(prefix="nav_bench_maps_"))
    shutil.copytree(REPO / "tests" / "data" / "maps", tmp, dirs_exist_ok=True)
    for gz in tmp.rglob("*.gz"):
        with gzip.open(gz, "rb") as fin, open(gz.with_suffix(""), "wb") as fout:
            shutil.copyfileobj(fin, fout)
    return tmp


def bench_grid_search() -> None:
    rng = np.random.default_rng(1)
    for label, blocked in (("empty", np.zeros((400, 400), bool)),
                           ("25% random", rng.random((400, 400)) < 0.25)):
        blocked[:3, :3] = blocked[-3:, -3:] = False
        t0 = time.perf_counter()
        found = grid_path(blocked, (0, 0), (399, 399))
        dt = time.perf_counter() - t0
        length = f"{found[0]:.2f} cells" if found else "unreachable"
        print(f"  400x400 {label:>10}: grid_path {dt * 1e3:6.1f} ms ({length})")
    # a 30 m x 30 m world of staggered walls (600 x 600 cells at 0.05 m)
    walls = [{"wall": {"from": [3.0 + 2.5 * i, 0.0 if i % 2 else 4.0],
                       "to": [3.0 + 2.5 * i, 26.0 if i % 2 else 30.0]}} for i in range(10)]
    world = world_from_data({"size": [30, 30], "start": [1, 2], "goal": [29, 28], "obstacles": walls})
    t0 = time.perf_counter()
    path = optimal_path(world, ROBOT_RADIUS)
    dt = time.perf_counter() - t0
    print(f"  optimal_path, 30 m x 30 m, 10 staggered walls: {dt * 1e3:.0f} ms, "
          f"{path.length_m:.2f} m ({len(path.points)} vertices; 8-connected {path.grid_length_m:.2f} m)")


def bench_movingai(maps: Path) -> None:
    for scen_file in sorted((maps / "movingai").glob("*.scen")):
        map_file = maps / "movingai" / (scen_file.name.split("-random")[0] + ".map")
        scenarios = read_scen(scen_file)
        data = import_movingai(map_file, scen_file, 0, cell=CELL)
        world = world_from_data(data)
        h = data["meta"]["cells"][1]
        geometry = static_geometry(world)
        blocked = rasterize(geometry, CELL).occupied  # the imported grid, row 0 at the bottom
        graph = grid_graph(blocked)
        t0 = time.perf_counter()
        errors = []
        for sc in scenarios:
            (sx, sy), (gx, gy) = sc.start, sc.goal
            d = grid_distances(blocked, (h - 1 - sy, sx), graph=graph)[h - 1 - gy, gx]
            errors.append(abs(d - sc.optimal) / sc.optimal)
        t_grid = time.perf_counter() - t0
        print(f"  {map_file.stem}: {len(world.obstacles)} boxes; {len(scenarios)} scenarios, "
              f".scen lengths reproduced, max relative error {max(errors):.2e} "
              f"({t_grid * 1e3 / len(scenarios):.2f} ms per line)")

        cspace = rasterize(geometry, 0.05, inflate=ROBOT_RADIUS)
        t0 = time.perf_counter()
        ratios, unreachable, grid_ratios = [], 0, []
        for sc in scenarios:
            start = ((sc.start[0] + 0.5) * CELL, (h - 1 - sc.start[1] + 0.5) * CELL)
            goal = ((sc.goal[0] + 0.5) * CELL, (h - 1 - sc.goal[1] + 0.5) * CELL)
            path = raster_optimal_path(cspace, start, goal, snap=ROBOT_RADIUS + 0.05)
            if path.length_m is None:
                unreachable += 1
                continue
            ratios.append(path.length_m / (sc.optimal * CELL))
            grid_ratios.append(path.grid_length_m / (sc.optimal * CELL))
        t_robot = time.perf_counter() - t0
        r = np.asarray(ratios)
        g = np.asarray(grid_ratios)
        print(f"    robot r={ROBOT_RADIUS} m optimal_path / (0.5 m x .scen): median {np.median(r):.4f}, "
              f"min {r.min():.4f}, max {r.max():.4f}, 5-95% [{np.percentile(r, 5):.4f}, "
              f"{np.percentile(r, 95):.4f}]; unreachable {unreachable}; "
              f"{t_robot * 1e3 / len(scenarios):.0f} ms per path")
        print(f"    (before smoothing, 8-connected on the 0.05 m C-space: median {np.median(g):.4f}, "
              f"min {g.min():.4f}, max {g.max():.4f})")


def bench_importers(maps: Path) -> None:
    cases = [("ros", maps / "ros" / "turtlebot3_world" / "map.yaml"),
             ("ros", maps / "ros" / "lse_arena" / "lse_arena.yaml")]
    cases += [("barn", p) for p in sorted((maps / "barn" / "worlds").glob("*.world"))]
    for kind, path in cases:
        t0 = time.perf_counter()
        data = import_ros(path) if kind == "ros" else import_barn(path)
        dt = time.perf_counter() - t0
        world = world_from_data(data)
        extra = ""
        if kind == "ros":
            w, h = data["meta"]["pixels"]
            occupied = rasterize(static_geometry(world), data["meta"]["resolution_m"]).occupied
            extra = f" ({w}x{h} px kept, {int(occupied.sum())} blocked px)"
        print(f"  {kind} {path.name}: {len(world.obstacles)} shapes{extra}, import {dt * 1e3:.0f} ms")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--maps", help="folder with ros/, movingai/, barn/ sample maps")
    args = parser.parse_args()
    maps = find_maps(args.maps)
    print(f"sample maps: {maps}")
    print("grid search:")
    bench_grid_search()
    print("MovingAI:")
    bench_movingai(maps)
    print("importers:")
    bench_importers(maps)


if __name__ == "__main__":
    main()
