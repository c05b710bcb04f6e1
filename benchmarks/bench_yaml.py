"""``nav-bench validate`` on a large world: libyaml's event parser vs PyYAML's pure-Python one.

    python benchmarks/bench_yaml.py [--cylinders N] [--repeat R] [--write FILE]

Writes a world of N cylinders (default 10,000; 134 m x 134 m), then times, median of R runs:

1. ``validate`` as the command line does it (read, parse with line numbers, validate the
   world model and its geometry) with nav-bench's composer on libyaml's C parser;
2. the same with the parser forced to PyYAML's pure-Python one (what ``validate`` used
   before: 13.7 s on this world on the project's machine), and PyYAML's own
   ``yaml.compose`` with the pure-Python loader (the old composer's first step alone).

``--write FILE`` only writes the world (for timing the whole process from outside:
``/usr/bin/time -v nav-bench validate FILE``).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import yaml

from nav_bench import yamlio
from nav_bench.validate import validate_paths


def write_world(path: Path, cylinders: int) -> Path:
    side = max(1, round(cylinders ** 0.5))
    pitch = 1.3  # 10,000 cylinders: a 134 m square, within the raster budget
    size = 2 + side * pitch + 2
    lines = ["name: many_cylinders", f"size: [{size:.1f}, {size:.1f}]", "start: [0.5, 0.5]",
             f"goal: [{size - 0.5:.1f}, {size - 0.5:.1f}]", "obstacles:"]
    for i in range(cylinders):
        x = 2 + (i % side) * pitch + (i * 7919 % 1000) / 1000
        y = 2 + (i // side) * pitch + (i * 104729 % 1000) / 1000
        lines.append(f"  - cylinder: {{center: [{x:.3f}, {y:.3f}], radius: 0.3}}")
    path.write_text("\n".join(lines) + "\n")
    return path


def _median_s(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cylinders", type=int, default=10_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--write", type=Path, help="only write the world to this file")
    args = ap.parse_args()
    if args.write:
        write_world(args.write, args.cylinders)
        print(f"wrote {args.write}")
        return
    with tempfile.TemporaryDirectory() as tmp:
        path = write_world(Path(tmp) / "many.yaml", args.cylinders)
        mb = path.stat().st_size / 1e6

        def check() -> None:
            problems, _ = validate_paths([path])
            assert not problems, problems

        fast = _median_s(check, args.repeat)
        c_parser = getattr(yaml, "CSafeLoader", None)
        print(f"world: {args.cylinders:,} cylinders, {mb:.1f} MB; libyaml present: "
              f"{c_parser is not None}")
        print(f"validate, libyaml events + nav-bench composer: {fast:8.3f} s")
        original = yamlio._event_parser
        yamlio._event_parser = yaml.SafeLoader  # the pure-Python parser, same composer
        try:
            slow = _median_s(check, args.repeat)
        finally:
            yamlio._event_parser = original
        print(f"validate, pure-Python parser, same composer:  {slow:8.3f} s  ({slow / fast:.1f}x)")
        text = path.read_text()
        compose = _median_s(lambda: yaml.compose(text, Loader=yaml.SafeLoader), args.repeat)
        print(f"yaml.compose with the pure-Python SafeLoader:  {compose:8.3f} s  "
              f"({compose / fast:.1f}x; the old path's first step alone)")


if __name__ == "__main__":
    main()
