"""``nav-bench``: the command line. Thin: parses arguments and calls the library.

Exit status: 0 success, 2 bad input (nothing simulated), 1 anything else, 130 interrupted
(Ctrl-C, SIGTERM); ``run --strict``: 3 when the run completed with error rows.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NoReturn

from nav_bench import __version__
from nav_bench.errors import InputError, NavBenchError
from nav_bench.interface import Outcome

Handler = Callable[[argparse.Namespace], int]

EXIT_INTERRUPTED = 130  # Ctrl-C or SIGTERM: the shell's convention for "ended by SIGINT"
EXIT_ERROR_ROWS = 3  # run --strict: the run completed, but some episodes are error rows


def _xy(text: str) -> tuple[float, float]:
    try:
        x, y = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected X,Y in metres, got {text!r}") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise argparse.ArgumentTypeError(f"expected finite X,Y in metres, got {text!r}")
    return (x, y)


def _int_from(low: int) -> Callable[[str], int]:
    """An argparse type: a whole number >= ``low`` (seeds >= 0, worker counts >= 1)."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"expected a whole number >= {low}, got {value}")
        return value

    return parse


def _positive(text: str) -> float:
    """An argparse type: a finite number > 0 (seconds, metres)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"expected a finite number > 0, got {text!r}")
    return value


def _key_value(text: str) -> tuple[str, Any]:
    import yaml

    key, eq, value = text.partition("=")
    if not eq or not key:
        raise argparse.ArgumentTypeError(f"expected key=value, got {text!r}")
    return key, yaml.safe_load(value)


# --------------------------------------------------------------------------- commands
def cmd_run(args: argparse.Namespace) -> int:
    from nav_bench.batch.runner import run_suite
    from nav_bench.batch.store import ResultsStore
    from nav_bench.paths import find

    suite = find("suite", args.suite).path if args.suite else None
    out = run_suite(suite, workers=args.workers, out=args.out, resume=args.resume,
                    executor=args.executor, progress=not args.quiet,
                    retry_errors=args.retry_errors)
    print(f"results: {out}")
    if args.record_failures:
        from nav_bench.batch.store import ResultsStore
        from nav_bench.reporting.replay import record_failures

        gifs = record_failures(ResultsStore(out).rows(), out)
        print(f"failures: {len(gifs)} GIFs beside their traces in {out / 'traces'}")
    if not args.no_report:
        from nav_bench.reporting.markdown import write_report

        report = write_report([out], out=None)
        print(f"report:  {report}")
    errors = sum(1 for r in ResultsStore(out).rows() if r.get("outcome") == "error")
    if errors:
        print(f"{errors} episodes ended in an error row (see their 'error' field); replay them "
              f"with: nav-bench run --resume {out} --retry-errors", file=sys.stderr)
        if args.strict:
            return EXIT_ERROR_ROWS
    return 0


def cmd_episode(args: argparse.Namespace) -> int:
    from nav_bench.episode import EpisodeSettings
    from nav_bench.episode.loop import run_episode
    from nav_bench.paths import find
    from nav_bench.planners.registry import parse_planner_arg
    from nav_bench.specs import load_robot
    from nav_bench.world.load import load_world

    world_file = find("world", args.world)
    world = load_world(world_file.path)
    planner = parse_planner_arg(args.planner)
    robot = load_robot(find("robot", args.robot).path) if args.robot else load_robot()
    from nav_bench.episode.protocol import make_protocol

    if args.time_limit is not None and make_protocol(args.protocol).time_limit_s is not None:
        raise InputError(f"protocol {args.protocol!r} sets the time limit itself; drop --time-limit")
    settings = EpisodeSettings(time_s=args.time_limit, protocol=args.protocol)
    if args.no_stuck:
        settings = dataclasses.replace(settings, stuck_s=None)
    live = None
    if args.live or args.record:
        from nav_bench.reporting.live import LiveView

        live = LiveView(world, every_s=0.5, show=args.live, save=args.record)
    result = run_episode(world, planner, seed=args.seed, robot=robot, settings=settings,
                         world_file=world_file.given, gui=args.gui, live=live)
    row = result.row
    if args.plot:
        from nav_bench.reporting.episode_plot import plot_episode

        plot_episode(result.trace, args.plot)
    if args.trace:
        result.trace.save(args.trace)
    if args.json:
        print(json.dumps(row.to_json(), default=str))
    else:
        print(f"{row.world} / {row.planner} seed {row.seed}: {row.outcome} in "
              f"{_fmt(row.time_s, 1)} s simulated ({row.wall_s:.2f} s wall), path "
              f"{_fmt(row.path_length_m)} m (optimal {_fmt(row.optimal_length_m)} m), "
              f"SPL {row.spl:.3f}, re-plans {row.replans}, collisions {row.collisions}, "
              f"min clearance {_fmt(row.min_clearance_m, 3)} m"
              + (f", barn_score {_fmt(row.barn_score, 3)}" if row.barn_score is not None else ""))
        if row.error:
            print(row.error, file=sys.stderr)
        if args.plot:
            print(f"plot: {args.plot}")
    return 0 if row.outcome is not Outcome.ERROR else 1


def _fmt(value: float | None, digits: int = 2) -> str:
    return "n/a" if value is None else f"{value:.{digits}f}"


def cmd_report(args: argparse.Namespace) -> int:
    from nav_bench.reporting.markdown import write_report

    path = write_report([Path(d) for d in args.dirs], out=args.out)
    print(f"report: {path}")
    return 0


def cmd_validate(args: argparse.Namespace) -> int:
    from nav_bench.validate import validate_paths

    problems, checked = validate_paths([Path(p) for p in args.paths])
    for message in problems:
        print(message, file=sys.stderr)
    print(f"{checked - len(problems)} of {checked} files valid")
    return 2 if problems or checked == 0 else 0


def cmd_show(args: argparse.Namespace) -> int:
    from nav_bench.paths import find
    from nav_bench.world.draw import save_world_png
    from nav_bench.world.load import load_world

    world = load_world(find("world", args.world).path)
    save_world_png(world, args.output)
    print(f"{world.name}: {world.size[0]:g} m x {world.size[1]:g} m, {len(world.obstacles)} "
          f"obstacles, {len(world.movers)} movers -> {args.output}")
    try:
        from nav_bench.world.difficulty import difficulty
    except ImportError:
        return 0
    for key, value in difficulty(world).items():
        shown = f"{value:.3f}" if isinstance(value, float) else "n/a (goal unreachable)" if value is None else value
        print(f"  {key:32s} {shown}")
    return 0


def cmd_planners(args: argparse.Namespace) -> int:
    from nav_bench.planners.registry import default_registry

    registry = default_registry()
    for name in registry.names():
        try:
            cls = registry.get(name)
        except NavBenchError as exc:
            print(f"{name}: cannot load ({exc})")
            continue
        doc = (cls.__doc__ or "").strip().splitlines()[0] if cls.__doc__ else ""
        print(f"{name}: {doc}")
        if cls.reference:
            print(f"  reference: {cls.reference}")
        for p in cls.params:
            unit = f" [{p.unit}]" if p.unit and p.unit != "-" else ""
            choices = f" one of {list(p.choices)}" if p.choices else ""
            print(f"  {p.name:24s} = {p.default!r:<10}{unit}  {p.doc}{choices}")
        print()
    return 0


def cmd_generate(args: argparse.Namespace) -> int:
    from nav_bench.world.generate import generate_world, list_generators, write_world_yaml

    if args.list or not args.kind:
        for name, info in list_generators().items():
            print(f"{name}: {info.doc}")
            for s in info.settings:
                print(f"  {s[0]:20s} = {s[1]!r:<10} [{s[2]}]  {s[3]}")
        return 0
    if not args.output:
        raise InputError("generate needs -o FILE")
    data = generate_world(args.kind, args.seed, dict(args.set or []))
    write_world_yaml(data, args.output)
    print(f"wrote {args.output}")
    return 0


def cmd_import(args: argparse.Namespace) -> int:
    from nav_bench.world import imports
    from nav_bench.world.load import world_from_data

    if args.format == "ros":
        data = imports.import_ros(Path(args.map), start=args.start, goal=args.goal,
                                  unknown_as=args.unknown)
    elif args.format == "movingai":
        data = imports.import_movingai(Path(args.map), scen=Path(args.scen) if args.scen else None,
                                       index=args.index, cell=args.cell)
    else:
        data = imports.import_barn(Path(args.map))
    world_from_data(data, file=args.output)  # refuse to write a world that would not load
    imports.write_world_yaml(data, args.output)
    print(f"wrote {args.output} ({len(data.get('obstacles', []))} obstacles)")
    return 0


def cmd_perf(args: argparse.Namespace) -> int:
    from nav_bench.perf import run_perf

    run_perf(world_file=args.world, seconds=args.seconds)
    return 0


def cmd_replay(args: argparse.Namespace) -> int:
    from nav_bench.reporting.replay import replay

    frames = replay(args.trace, args.record, every_s=args.every, fps=args.fps)
    print(f"wrote {args.record} ({frames} frames)")
    return 0


def cmd_list(args: argparse.Namespace) -> int:
    from nav_bench.paths import KIND_FOLDERS, data_root, describe

    kinds = {"suites": "suite", "worlds": "world", "sets": "planner set", "robots": "robot"}
    for heading, kind in kinds.items():
        if args.kind not in (None, heading):
            continue
        print(f"{heading} ({KIND_FOLDERS[kind]}/):")
        for name, line in describe(kind):
            print(f"  {name:28s} {line[:100]}")
        print()
    print(f"shipped data: {data_root()}\nnames work wherever a file does; a file of yours, "
          "given as a path, comes first")
    return 0


# --------------------------------------------------------------------------- parser
class _Parser(argparse.ArgumentParser):
    """Argument errors in one line (``--help`` shows the usage), exit status 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="nav-bench",
        description="Benchmark mobile-robot navigation in a-priori unknown indoor worlds (PyBullet).")
    parser.add_argument("--version", action="version", version=f"nav-bench {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("run", help="run a batch benchmark (default suite: configs/suites/default.yaml)")
    p.add_argument("suite", nargs="?",
                   help="suite YAML or shipped suite name, e.g. smoke (default: the default suite)")
    p.add_argument("--workers", type=_int_from(1), help="parallel worker processes (default: CPU cores)")
    p.add_argument("--out", type=Path, help="results folder (default: results/<suite>-<timestamp>)")
    p.add_argument("--resume", type=Path, help="finish an interrupted results folder")
    p.add_argument("--executor", default="local",
                   help="local (process pool), dask (local cluster) or dask:tcp://HOST:PORT")
    p.add_argument("--retry-errors", action="store_true",
                   help="with --resume: also replay the episodes whose row is an error")
    p.add_argument("--strict", action="store_true",
                   help=f"exit with status {EXIT_ERROR_ROWS} if any episode is an error row")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--no-report", action="store_true", help="do not write report.md at the end")
    p.add_argument("--record-failures", action="store_true",
                   help="keep a GIF of each episode that did not reach its goal, beside its trace")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("episode", help="play one episode")
    p.add_argument("world", help="world YAML or shipped world name (paper/long_wall)")
    p.add_argument("--planner", default="eopc",
                   help="name, parameter set (file or shipped name), or name:key=value,... "
                        "(default: eopc)")
    p.add_argument("--seed", type=_int_from(0), default=0)
    p.add_argument("--robot", help="robot config YAML or name (default: robots/diffbot.yaml)")
    p.add_argument("--time-limit", type=_positive, help="simulated seconds (default: scales with world size)")
    p.add_argument("--no-stuck", action="store_true", help="do not end the episode when the robot stalls")
    p.add_argument("--protocol", default="nav_bench",
                   help="the rules the episode is judged by: nav_bench (default) or barn "
                        "(1 m goal radius, 100 s, a collision ends it, barn_score)")
    p.add_argument("--plot", help="write a PNG of the map, trajectory and planner state")
    p.add_argument("--trace", help="write the trace (.npz) for replotting")
    p.add_argument("--json", action="store_true", help="print exactly one result row (JSON) on stdout")
    p.add_argument("--gui", action="store_true", help="open the PyBullet GUI (needs a display)")
    p.add_argument("--live", action="store_true", help="a live map window, redrawn every 0.5 s simulated")
    p.add_argument("--record", help="write the live map as an animated .gif or .mp4 (no screen needed)")
    p.set_defaults(func=cmd_episode)

    p = sub.add_parser("report", help="tables and figures from stored results")
    p.add_argument("dirs", nargs="+", help="results folder(s); two or more are compared")
    p.add_argument("--out", type=Path, help="report folder (default: inside the first results folder)")
    p.set_defaults(func=cmd_report)

    p = sub.add_parser("validate", help="check world, planner, robot and suite files")
    p.add_argument("paths", nargs="+", help="files or folders (folders: every *.yaml below)")
    p.set_defaults(func=cmd_validate)

    p = sub.add_parser("show", help="draw a world from above and print its difficulty measures")
    p.add_argument("world")
    p.add_argument("-o", "--output", required=True, help="PNG file")
    p.set_defaults(func=cmd_show)

    p = sub.add_parser("planners", help="list registered planners and their parameters")
    p.set_defaults(func=cmd_planners)

    p = sub.add_parser("generate", help="write a world YAML from a seeded generator")
    p.add_argument("kind", nargs="?", help="generator name (see --list)")
    p.add_argument("--seed", type=_int_from(0), default=0)
    p.add_argument("--set", type=_key_value, action="append", metavar="KEY=VALUE",
                   help="generator setting (repeatable)")
    p.add_argument("-o", "--output", help="world YAML to write")
    p.add_argument("--list", action="store_true", help="list generators and their settings")
    p.set_defaults(func=cmd_generate)

    p = sub.add_parser("import", help="turn an existing map into a world YAML")
    fmt = p.add_subparsers(dest="format", required=True, metavar="FORMAT")
    q = fmt.add_parser("ros", help="ROS map_server map (PGM/PNG + YAML)")
    q.add_argument("map", help="map YAML")
    q.add_argument("--start", type=_xy, help="X,Y in the map frame (default: chosen automatically)")
    q.add_argument("--goal", type=_xy, help="X,Y in the map frame (default: chosen automatically)")
    q.add_argument("--unknown", choices=("obstacle", "free"), default="obstacle",
                   help="what unknown cells become (default: obstacle)")
    q.add_argument("-o", "--output", required=True)
    q = fmt.add_parser("movingai", help="MovingAI .map grid (start/goal from a .scen line)")
    q.add_argument("map")
    q.add_argument("--scen", help=".scen file")
    q.add_argument("--index", type=_int_from(0), default=0, help="scenario line (0 = first)")
    q.add_argument("--cell", type=_positive, default=0.5, help="cell size in metres (default 0.5)")
    q.add_argument("-o", "--output", required=True)
    q = fmt.add_parser("barn", help="BARN .world (SDF) with the BARN protocol's start and goal")
    q.add_argument("map")
    q.add_argument("-o", "--output", required=True)
    p.set_defaults(func=cmd_import)

    p = sub.add_parser("replay", help="re-render a stored episode (trace .npz) as a .gif or .mp4")
    p.add_argument("trace", help="a trace .npz (nav-bench episode --trace, or a results folder's "
                                 "traces/)")
    p.add_argument("--record", required=True, help="the .gif or .mp4 to write")
    p.add_argument("--every", type=float, default=0.5, help="simulated seconds between frames")
    p.add_argument("--fps", type=float, help="playback frames per second (default: real time)")
    p.set_defaults(func=cmd_replay)

    p = sub.add_parser("list", help="list the shipped suites, worlds, parameter sets and robots")
    p.add_argument("kind", nargs="?", choices=("suites", "worlds", "sets", "robots"),
                   help="only this kind (sets: planner parameter sets)")
    p.set_defaults(func=cmd_list)

    p = sub.add_parser("perf", help="measure simulation and episode speed on this machine")
    p.add_argument("--world", default="worlds/paper/open_room.yaml",
                   help="world of the measured goal_seek episode (default: the open room)")
    p.add_argument("--seconds", type=_positive, help="time limit of that episode (default: the world's)")
    p.set_defaults(func=cmd_perf)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except NavBenchError as exc:
        print(f"nav-bench {args.command}: error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:  # the reader closed the pipe (`nav-bench list | head`): stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no error at exit's flush
        return 0
    except OSError as exc:  # a file nav-bench had to write or read failed: one line, not a traceback
        from nav_bench.batch.store import describe_os_error

        print(f"nav-bench {args.command}: error: {describe_os_error(exc)}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    raise SystemExit(main())
