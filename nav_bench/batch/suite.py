"""The suite file: which worlds, parameter sets, robots, seeds and limits a batch plays.

A suite (INTERFACES.md, "Suite") is read by :func:`load_suite` into a :class:`Suite` whose
every part is validated: world files are loaded, generator families are generated, parameter
names are checked against their planner, robot overrides against the robot model. Nothing is
simulated before all of it passed. :func:`expand` turns a suite into the list of
:class:`EpisodeJob` the runner plays: worlds x parameter sets x robot variants x seeds.

A suite with every kind of entry::

    name: sweep_demo                      # default: the file's stem; names the results folder
    worlds:
      - worlds/paper/*.yaml               # files, folders and globs
      - {generate: maze, seeds: "0..9", set: {cells: [8, 8]}}   # worlds maze_0 .. maze_9
    planners:                             # label -> parameter set
      eopc_paper: configs/planners/eopc_paper.yaml
      goal_seek: goal_seek                # a planner name, or name:key=value,...
      eopc_rr: {planner: eopc, params: {RR: [0.4, 0.5, 0.6]}}   # three sets
    seeds: 5                              # 0..4, or [3, 7], or "10..19"
    limits: {time_s: 300, stuck_s: 30, goal_tolerance: 0.2, control_hz: 10,
             physics_hz: 240, wall_s: 900}  # wall_s: wall-clock s before a hung episode is killed
    robot: {file: robots/diffbot.yaml, sonar: {noise_std: [0.0, 0.02]}}   # two robot variants
    protocol: nav_bench                   # or barn, or {name: barn, time_limit_s: 200}

Sweeps: a list where a single value is expected (a planner parameter, a robot setting) plays
one set per value; several lists play their grid product. Labels say which value is which:
``eopc_rr[RR=0.4]``, ``diffbot[sonar.noise_std=0.02]``.

Paths (world files and globs, parameter-set files, robot files, URDFs) are looked up relative
to the working folder first, then to the suite file's folder, then to the project's folder.

Every job has a stable ``job_id`` built from what decides its result (world contents,
planner and full parameters, robot, seed, limits), so a resumed run finds the jobs it has
done, and an edited world or suite cannot be mistaken for the one that was run.
"""

from __future__ import annotations

import glob
import itertools
import math
import os
import re
from collections.abc import Iterable
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Annotated, Any

from pydantic import Field, PositiveFloat

from nav_bench.episode.protocol import PROTOCOLS, make_protocol, protocol_of
from nav_bench.episode.settings import EpisodeSettings
from nav_bench.errors import InputError, SpecError, SpecErrors, UnknownNameError, format_key_path
from nav_bench.ids import robot_id, stable_id
from nav_bench.paths import project_file, project_roots
from nav_bench.planners.registry import (
    check_params,
    identity_params,
    load_planner_set,
    parse_planner_arg,
    set_id,
)
from nav_bench.specs import (
    PlannerSetSpec,
    RobotSpec,
    Strict,
    WorldSpec,
    load_robot,
)
from nav_bench.world.load import load_world, world_from_data
from nav_bench.yamlio import LineIndex, load_yaml, validate

Loc = tuple[str | int, ...]

_LABEL = re.compile(r"^[A-Za-z0-9_.+-]+$")
_GLOB_CHARS = frozenset("*?[")


# --------------------------------------------------------------------------- file models
class GeneratorFamily(Strict):
    """Worlds from a seeded generator (``nav_bench.world.generate``): one world per seed."""

    generate: str  # generator kind, e.g. "maze"
    name: str | None = None  # worlds are named <name>_<seed>; default: the kind
    seeds: int | str | list[int]  # a count N (0..N-1), "a..b" (a to b inclusive), or a list
    settings: dict[str, Any] = Field(default_factory=dict, alias="set")  # generator settings


class InlinePlannerSet(Strict):
    """A parameter set written in the suite; list values sweep."""

    planner: str
    params: dict[str, Any] = Field(default_factory=dict)


DEFAULT_WALL_S = 900.0  # a hung episode is killed after this many wall-clock seconds
MAX_WALL_S = 7 * 86400.0


class Limits(Strict):
    """Episode limits. A key left out takes the episode's default (``EpisodeSettings``)."""

    time_s: PositiveFloat | None = None  # simulated s; null: scales with the world's size
    stuck_s: PositiveFloat | None = None  # s without progress that end an episode; null: never
    stuck_radius: PositiveFloat | None = None  # m
    stuck_area_radius: PositiveFloat | None = None  # m, the oscillating robot's disc (3 x stuck_s)
    goal_tolerance: PositiveFloat | None = None  # m
    control_hz: PositiveFloat | None = None  # planner cycles per second
    # physics steps per second (default 60: results/fidelity/README.md; 240 plays the reference)
    physics_hz: PositiveFloat | None = None
    # wall-clock s per episode before it is killed; null: 900. At most a week: a bound a
    # timer can hold
    wall_s: Annotated[float, Field(gt=0.0, le=MAX_WALL_S)] | None = None




class SuiteFile(Strict):
    """The top level of a suite YAML. Entries are checked one by one afterwards (exact lines)."""

    name: str | None = None
    description: str = ""
    worlds: list[Any] = Field(min_length=1)
    planners: dict[str, Any] = Field(min_length=1)
    seeds: Any = 1
    limits: Limits = Limits()
    robot: Any = None
    protocol: Any = "nav_bench"  # a protocol name, or {name: NAME, <setting>: value, ...}


# --------------------------------------------------------------------------- expanded suite
@dataclass(frozen=True)
class WorldItem:
    """One world of the suite. ``file`` is the path as given (None for generated worlds until
    the runner writes them into the results folder); ``source`` says where it came from."""

    name: str
    spec: WorldSpec
    file: str | None
    source: dict[str, Any]
    digest: str  # stable hash of the world's contents


@dataclass(frozen=True)
class PlannerItem:
    """One parameter set: its label, the set as given, and the full parameters."""

    label: str
    spec: PlannerSetSpec
    params: dict[str, Any]
    params_id: str


@dataclass(frozen=True)
class RobotItem:
    """One robot variant."""

    label: str
    spec: RobotSpec
    robot_id: str


@dataclass(frozen=True)
class Suite:
    """A validated suite, ready to :func:`expand`."""

    name: str
    description: str
    file: str | None
    cwd: str
    data: dict[str, Any]  # the suite as written (stored in run.json, re-read on resume)
    worlds: tuple[WorldItem, ...]
    planners: tuple[PlannerItem, ...]
    robots: tuple[RobotItem, ...]
    seeds: tuple[int, ...]
    settings: dict[str, Any]  # full EpisodeSettings as a dict
    wall_s: float | None


@dataclass(frozen=True)
class EpisodeJob:
    """One episode to play. Plain picklable data: it travels to worker processes and clusters."""

    job_id: str
    world: WorldSpec
    world_name: str
    world_file: str | None
    label: str
    planner: PlannerSetSpec
    params: dict[str, Any]
    params_id: str
    robot: RobotSpec
    robot_label: str
    robot_id: str
    seed: int
    settings: dict[str, Any]
    wall_s: float | None = None

    def summary(self) -> dict[str, Any]:
        """The job without its world data, as stored in run.json."""
        return {"job_id": self.job_id, "world": self.world_name, "world_file": self.world_file,
                "label": self.label, "planner": self.planner.planner, "params_id": self.params_id,
                "robot": self.robot_label, "robot_id": self.robot_id, "seed": self.seed}


# --------------------------------------------------------------------------- helpers
def _line(index: LineIndex | None, loc: Loc) -> int | None:
    return index.line_of(loc) if index else None


def _err(problem: str, file: str | None, index: LineIndex | None, loc: Loc) -> SpecError:
    return SpecError(problem, file=file, key_path=format_key_path(loc), line=_line(index, loc))


def _sub_index(index: LineIndex | None, prefix: Loc) -> LineIndex | None:
    """The lines of the part of a document under ``prefix``, with ``prefix`` removed."""
    if index is None:
        return None
    n = len(prefix)
    return LineIndex({loc[n:]: line for loc, line in index.lines.items() if loc[:n] == prefix})


def _prefixed(err: SpecError, prefix: Loc, index: LineIndex | None, file: str | None) -> SpecError:
    """``err`` (about a part of the suite validated on its own) relocated into the suite."""
    key = format_key_path(prefix) + ("." + err.key_path if err.key_path else "")
    loc = (*prefix, *_split_key_path(err.key_path))
    return SpecError(err.problem, file=file, key_path=key, line=_line(index, loc) or err.line)


def _split_key_path(key_path: str) -> Loc:
    out: list[str | int] = []
    for part in re.findall(r"[^.\[\]]+|\[\d+\]", key_path):
        out.append(int(part[1:-1]) if part.startswith("[") else part)
    return tuple(out)


def slug(text: str) -> str:
    """``text`` as a file-name-safe word: letters, digits and ``._=+-`` kept."""
    return re.sub(r"-{2,}", "-", re.sub(r"[^A-Za-z0-9._=+-]", "-", text)).strip("-") or "x"


def _format_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):  # shortest exact form, "1" rather than "1.0"
        text = repr(value)
        return text[:-2] if text.endswith(".0") else text
    return str(value)


MAX_SEEDS = 100_000  # seeds of one suite or generator family
MAX_SWEEP = 10_000  # parameter sets (or robot variants) one sweep may make
MAX_EPISODES = 1_000_000  # episodes of one suite


def sweep_size(values: dict[str, Any]) -> int:
    """How many combinations :func:`sweep` would make (without making them)."""
    return math.prod(len(v) for v in values.values() if isinstance(v, list))


def sweep(values: dict[str, Any]) -> list[tuple[dict[str, Any], str]]:
    """Grid product over the list values of a flat mapping: ``[(values, "k=v,...")]``.

    Mappings without lists give one combination with an empty suffix. Keys keep their order.
    """
    keys = [k for k, v in values.items() if isinstance(v, list)]
    if not keys:
        return [(dict(values), "")]
    out = []
    for combo in itertools.product(*(values[k] for k in keys)):
        chosen = dict(values)
        chosen.update(zip(keys, combo, strict=True))
        out.append((chosen, ",".join(f"{k}={_format_value(v)}" for k, v in zip(keys, combo,
                                                                                 strict=True))))
    return out


def _flatten(tree: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    out: dict[str, Any] = {}
    for k, v in tree.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(_flatten(v, key + "."))
        else:
            out[key] = v
    return out


def _unflatten(flat: dict[str, Any]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, v in flat.items():
        node = out
        *parents, last = key.split(".")
        for p in parents:
            node = node.setdefault(p, {})
        node[last] = v
    return out


def parse_seeds(value: Any, *, what: str = "seeds") -> list[int]:
    """A count ``N`` (0..N-1), a range text ``"a..b"`` (a to b, inclusive) or a list of seeds."""
    if isinstance(value, bool):
        raise ValueError(f"{what}: expected a count, 'a..b' or a list of integers, got {value!r}")
    if isinstance(value, int):
        if value < 1:
            raise ValueError(f"{what}: a count must be at least 1, got {value}")
        if value > MAX_SEEDS:
            raise ValueError(f"{what}: at most {MAX_SEEDS:,} seeds, got {value:,}")
        return list(range(value))
    if isinstance(value, str):
        m = re.fullmatch(r"\s*(\d+)\s*\.\.\s*(\d+)\s*", value)
        if not m or int(m[1]) > int(m[2]):
            raise ValueError(f"{what}: expected 'a..b' with 0 <= a <= b (inclusive), got {value!r}")
        if int(m[2]) - int(m[1]) >= MAX_SEEDS or int(m[2]) >= 2**63:
            raise ValueError(f"{what}: at most {MAX_SEEDS:,} seeds, each below 2**63, got "
                             f"{value!r}")
        return list(range(int(m[1]), int(m[2]) + 1))
    if isinstance(value, list) and value:
        if not all(isinstance(s, int) and not isinstance(s, bool) and 0 <= s < 2**63
                   for s in value):
            raise ValueError(f"{what}: a list of seeds must hold integers from 0 to 2**63 - 1")
        if len(value) > MAX_SEEDS:
            raise ValueError(f"{what}: at most {MAX_SEEDS:,} seeds, got {len(value):,}")
        if len(set(value)) != len(value):
            raise ValueError(f"{what}: the list repeats a seed")
        return list(value)
    raise ValueError(f"{what}: expected a count, 'a..b' or a non-empty list of integers, "
                     f"got {value!r}")


class _Resolver:
    """Looks paths up relative to the working folder, then to the suite's folder, then to the
    project's folder (where ``worlds/`` and ``configs/`` ship), so the shipped suites work
    from any working folder."""

    def __init__(self, cwd: Path, suite_dir: Path | None) -> None:

        self.cwd = cwd
        self._roots = [p.resolve() for p in project_roots()]
        bases = [cwd, *([suite_dir] if suite_dir else []), *self._roots]
        self._bases = list(dict.fromkeys(bases))  # in order, without repeats

    def bases(self) -> list[Path]:
        return self._bases

    def _as_given(self, base: Path, rel: str) -> str:
        """The path as the user would write it: relative to the working folder when possible."""
        if Path(rel).is_absolute() or base == self.cwd:
            return rel
        path = base / rel
        if _inside(path, self.cwd):
            return os.path.relpath(path, self.cwd)
        # a shipped file: recorded below its root, the same from a checkout or a wheel
        return rel if base in self._roots else str(path)

    def file(self, text: str) -> tuple[Path, str] | None:
        """(absolute path, path as given) of an existing file, or None."""
        for base in self.bases():
            p = base / text
            if p.is_file():
                return p.resolve(), self._as_given(base, text)
        return None

    def worlds(self, text: str) -> list[tuple[Path, str]]:
        """World files of an entry: a file, a folder (its *.yaml) or a glob; sorted."""
        for base in self.bases():
            if _GLOB_CHARS & set(text):
                hits = sorted(glob.glob(text, root_dir=base, recursive=True))
                hits = [h for h in hits if (base / h).is_file()]
            elif (base / text).is_dir():
                hits = sorted(str(Path(text) / p.name) for p in (base / text).iterdir()
                              if p.suffix in (".yaml", ".yml") and p.is_file())
            elif (base / text).is_file():
                hits = [text]
            else:
                hits = []
            if hits:
                return [((base / h).resolve(), self._as_given(base, h)) for h in hits]
        return []


def _inside(path: Path, folder: Path) -> bool:
    try:
        path.resolve().relative_to(folder.resolve())
    except ValueError:
        return False
    return True


# --------------------------------------------------------------------------- loading
def default_suite_file() -> Path:
    """``configs/suites/default.yaml`` of the project."""

    return project_file("configs/suites/default.yaml")


def load_suite(path: str | Path, *, cwd: str | Path | None = None) -> Suite:
    """Read and validate a suite file; :class:`SpecError` names the file, key path and line."""
    data, index = load_yaml(path)
    return suite_from_data(data, file=str(path), index=index, cwd=cwd)


def suite_from_data(data: Any, *, file: str | None = None, index: LineIndex | None = None,
                    cwd: str | Path | None = None) -> Suite:
    """Validate parsed suite data. Relative paths: ``cwd`` (default: the working folder)
    first, then the folder of ``file``."""
    cwd_path = Path(cwd) if cwd is not None else Path.cwd()
    suite_dir = (cwd_path / file).resolve().parent if file else None
    top = validate(SuiteFile, data, file=file, index=index)
    resolver = _Resolver(cwd_path.resolve(), suite_dir)
    name = top.name or (Path(file).stem if file else "suite")
    if not _LABEL.match(name):
        raise _err(f"suite name {name!r} may hold only letters, digits and _ . + -",
                   file, index, ("name",))
    try:
        seeds = parse_seeds(top.seeds)
    except ValueError as exc:
        raise _err(str(exc), file, index, ("seeds",)) from None
    settings, wall_s = _settings(top.limits, top.protocol, file, index)
    worlds = _worlds(top.worlds, resolver, file, index)
    _check_goal_distances(worlds, settings["goal_tolerance"], file, index)
    planners = _planners(top.planners, resolver, file, index)
    robots = _robots(top.robot, resolver, file, index)
    episodes = len(worlds) * len(planners) * len(robots) * len(seeds)
    if episodes > MAX_EPISODES:
        raise _err(f"the suite makes {episodes:,} episodes, more than {MAX_EPISODES:,}",
                   file, index, ())
    return Suite(name=name, description=top.description, file=file, cwd=str(cwd_path.resolve()),
                 data=data, worlds=tuple(worlds), planners=tuple(planners), robots=tuple(robots),
                 seeds=tuple(seeds), settings=settings, wall_s=wall_s)


def _settings(limits: Limits, protocol: Any, file: str | None,
              index: LineIndex | None) -> tuple[dict[str, Any], float | None]:
    given = limits.model_dump(exclude_unset=True)
    wall_s = given.pop("wall_s", DEFAULT_WALL_S)
    given.update(_protocol(protocol, given, file, index))
    try:
        settings = EpisodeSettings(**given)
    except InputError as exc:
        raise _err(str(exc), file, index, ("limits",)) from None
    return asdict(settings), wall_s


def _protocol(entry: Any, limits: dict[str, Any], file: str | None,
              index: LineIndex | None) -> dict[str, Any]:
    """``protocol`` and ``protocol_options`` of the episode settings from the suite's
    ``protocol:`` entry; unknown names and settings are refused with the allowed ones, and so
    are limits that contradict the protocol's own rules."""
    if isinstance(entry, str):
        name, options, loc = entry, {}, ("protocol",)
    elif isinstance(entry, dict) and isinstance(entry.get("name"), str):
        name = entry["name"]
        options = {k: v for k, v in entry.items() if k != "name"}
        loc = ("protocol", next(iter(options))) if options else ("protocol",)
    else:
        raise _err(f"expected a protocol name ({', '.join(PROTOCOLS)}) or {{name: NAME, setting: "
                   f"value}}, got {entry!r}", file, index, ("protocol",))
    try:
        rules = make_protocol(name, options)
    except InputError as exc:
        bad = next((k for k in options if k in str(exc)), None)
        where = ("protocol", bad) if bad else (("protocol", "name") if isinstance(entry, dict) else loc)
        raise _err(str(exc), file, index, where) from None
    fixed = {"goal_tolerance": rules.goal_radius_m, "time_s": rules.time_limit_s}
    for key, value in fixed.items():
        if value is not None and key in limits:
            setting = "goal_radius_m" if key == "goal_tolerance" else "time_limit_s"
            raise _err(f"protocol {name!r} sets this itself ({value:g}); change it with "
                       f"protocol: {{name: {name}, {setting}: ...}}", file, index, ("limits", key))
    return {"protocol": name, "protocol_options": options}


def _worlds(entries: list[Any], resolver: _Resolver, file: str | None,
            index: LineIndex | None) -> list[WorldItem]:
    items: list[WorldItem] = []
    seen_files: set[Path] = set()
    by_name: dict[str, WorldItem] = {}
    for i, entry in enumerate(entries):
        loc: Loc = ("worlds", i)
        if isinstance(entry, str):
            new = _world_files(entry, resolver, seen_files, file, index, loc)
        elif isinstance(entry, dict):
            family = validate(GeneratorFamily, entry, file=file, index=index, prefix=loc)
            new = _generated_worlds(family, file, index, loc)
        else:
            raise _err("expected a file, a folder, a glob, or {generate: KIND, seeds: ...}, "
                       f"got {entry!r:.60}", file, index, loc)
        for item in new:
            other = by_name.get(item.name)
            if other is not None:
                raise _err(f"two worlds are named {item.name!r} ({_where(other)} and "
                           f"{_where(item)}); results are grouped by world name: give one of "
                           f"them its own 'name:'", file, index, loc)
            by_name[item.name] = item
            items.append(item)
    return items


def _check_goal_distances(worlds: list[WorldItem], tolerance: float, file: str | None,
                          index: LineIndex | None) -> None:
    """Every world's goal lies beyond the suite's success radius from its start."""
    from nav_bench.world.geometry import check_goal_distance

    for item in worlds:
        try:
            check_goal_distance(item.spec, tolerance)
        except SpecError as exc:
            raise _err(f"world {item.name!r} ({_where(item)}): goal {exc.problem}", file, index,
                       ("limits", "goal_tolerance")) from None


def _where(item: WorldItem) -> str:
    if item.file:
        return item.file
    return f"generator {item.source['generate']} seed {item.source['seed']}"


def _world_files(entry: str, resolver: _Resolver, seen: set[Path], file: str | None,
                 index: LineIndex | None, loc: Loc) -> list[WorldItem]:
    hits = resolver.worlds(entry)
    if not hits:
        where = " or ".join(str(b) for b in resolver.bases())
        raise _err(f"{entry!r} matches no world file (looked in {where})", file, index, loc)

    items = []
    for path, given in hits:
        if path in seen:  # two globs naming the same file play it once
            continue
        seen.add(path)
        world = load_world(path)  # errors name the world file, key path and line
        items.append(_world_item(world, given, {"file": given}))
    return items


def _world_item(world: WorldSpec, file: str | None, source: dict[str, Any]) -> WorldItem:
    assert world.name is not None
    digest = stable_id(world.model_dump(mode="json", by_alias=True), length=16)
    return WorldItem(name=world.name, spec=world, file=file, source=source, digest=digest)


def _generated_worlds(family: GeneratorFamily, file: str | None, index: LineIndex | None,
                      loc: Loc) -> list[WorldItem]:
    try:
        seeds = parse_seeds(family.seeds, what="seeds")
    except ValueError as exc:
        raise _err(str(exc), file, index, (*loc, "seeds")) from None
    try:  # imported only when a suite asks for generated worlds
        from nav_bench.world.generate import generate_world
    except ImportError as exc:
        raise _err(f"world generators are not available ({exc})", file, index,
                   (*loc, "generate")) from None
    items = []
    for seed in seeds:
        try:
            data = generate_world(family.generate, seed, dict(family.settings))
        except SpecError as exc:
            raise _err(exc.problem, file, index, (*loc, "set")) from None
        except UnknownNameError as exc:
            raise _err(str(exc), file, index, (*loc, "generate")) from None
        except InputError as exc:
            raise _err(str(exc), file, index, (*loc, "set")) from None
        default_name = f"{family.name or family.generate}_{seed}"
        data = {**data, "name": default_name}
        try:
            world = world_from_data(data, name=default_name)
        except (SpecError, SpecErrors) as exc:
            raise _err(f"generator {family.generate!r} made an invalid world for seed {seed}: "
                       f"{exc}", file, index, loc) from None
        source = {"generate": family.generate, "seed": seed, "set": dict(family.settings)}
        items.append(_world_item(world, None, source))
    return items


def _planners(entries: dict[str, Any], resolver: _Resolver, file: str | None,
              index: LineIndex | None) -> list[PlannerItem]:

    items: list[PlannerItem] = []
    labels: set[str] = set()
    for label, entry in entries.items():
        loc: Loc = ("planners", label)
        if not isinstance(label, str) or not _LABEL.match(label):
            raise _err(f"label {label!r} may hold only letters, digits and _ . + -",
                       file, index, loc)
        sets: list[tuple[PlannerSetSpec, str]]
        if isinstance(entry, str):
            if entry.endswith((".yaml", ".yml")):
                found = resolver.file(entry)
                if found is None:
                    where = " or ".join(str(b) for b in resolver.bases())
                    raise _err(f"parameter-set file {entry!r} not found (looked in {where})",
                               file, index, loc)
                sets = [(load_planner_set(found[0]), "")]
            else:
                try:
                    sets = [(parse_planner_arg(entry), "")]
                except InputError as exc:
                    raise _err(str(exc), file, index, loc) from None
        elif isinstance(entry, dict):
            inline = validate(InlinePlannerSet, entry, file=file, index=index, prefix=loc)
            for key, value in inline.params.items():
                if isinstance(value, list) and not value:
                    raise _err("an empty list sweeps nothing", file, index, (*loc, "params", key))
            if sweep_size(inline.params) > MAX_SWEEP:
                raise _err(f"the lists sweep {sweep_size(inline.params):,} parameter sets, more "
                           f"than {MAX_SWEEP:,}", file, index, (*loc, "params"))
            sub = _sub_index(index, loc)
            sets = []
            for params, suffix in sweep(inline.params):
                try:
                    check_params(inline.planner, params, file=file, index=sub)
                except SpecError as exc:
                    raise _prefixed(exc, loc, index, file) from None
                sets.append((PlannerSetSpec(planner=inline.planner, params=params), suffix))
        else:
            raise _err("expected a parameter-set file, a planner name (name:key=value,...) or "
                       "{planner: NAME, params: {...}}", file, index, loc)
        for spec, suffix in sets:
            full = check_params(spec.planner, spec.params)
            item_label = f"{label}[{suffix}]" if suffix else label
            if item_label in labels:
                raise _err(f"label {item_label!r} is used twice", file, index, loc)
            labels.add(item_label)
            items.append(PlannerItem(label=item_label, spec=spec, params=full,
                                     params_id=set_id(spec.planner, full)))
    return items


def _robots(entry: Any, resolver: _Resolver, file: str | None,
            index: LineIndex | None) -> list[RobotItem]:

    loc: Loc = ("robot",)
    robot_file: Path | None = None
    overrides: dict[str, Any] = {}
    if isinstance(entry, str):
        entry = {"file": entry}
    if entry is not None and not isinstance(entry, dict):
        raise _err("expected a robot file or a mapping {file: ..., <overrides>}", file, index, loc)
    entry = dict(entry or {})
    label = entry.pop("label", None)
    if "file" in entry:
        text = entry.pop("file")
        found = resolver.file(str(text))
        if found is None:
            where = " or ".join(str(b) for b in resolver.bases())
            raise _err(f"robot file {text!r} not found (looked in {where})", file, index,
                       (*loc, "file"))
        robot_file = found[0]
    overrides = entry
    flat = _flatten(overrides)
    for key, value in flat.items():
        if isinstance(value, list) and not value:
            raise _err("an empty list sweeps nothing", file, index, (*loc, *key.split(".")))
    if sweep_size(flat) > MAX_SWEEP:
        raise _err(f"the lists sweep {sweep_size(flat):,} robot variants, more than "
                   f"{MAX_SWEEP:,}", file, index, loc)
    items = []
    for chosen, suffix in sweep(flat):
        chosen = dict(chosen)
        if isinstance(chosen.get("urdf"), str):  # a URDF swap: a path like any other in the suite
            found = resolver.file(chosen["urdf"])
            if found is None:
                where = " or ".join(str(b) for b in resolver.bases())
                raise _err(f"URDF {chosen['urdf']!r} not found (looked in {where})",
                           file, index, (*loc, "urdf"))
            chosen["urdf"] = str(found[0])
        try:
            robot = load_robot(robot_file, _unflatten(chosen) or None)
        except SpecError as exc:
            raise _robot_error(exc, overrides, loc, file, index) from None
        except SpecErrors as exc:
            raise _robot_error(exc.errors[0], overrides, loc, file, index) from None
        base = label or robot.name or "robot"
        items.append(RobotItem(label=f"{base}[{suffix}]" if suffix else base, spec=robot,
                               robot_id=robot_id(robot)))
    return items


def _robot_error(exc: SpecError, overrides: dict[str, Any], loc: Loc, file: str | None,
                 index: LineIndex | None) -> SpecError:
    """Point at the suite's line when the suite's override caused the error."""
    if any(exc.key_path == k or exc.key_path.startswith((f"{k}.", f"{k}["))
           for k in map(str, overrides)):
        return _prefixed(exc, loc, index, file)
    return exc


# --------------------------------------------------------------------------- expansion
def job_id(world: WorldItem, planner: PlannerItem, robot: RobotItem, seed: int,
           settings: dict[str, Any]) -> str:
    """Readable and content-addressed: ``<world>__<label>__<robot>__s<seed>__<hash>``."""
    params = identity_params(planner.spec.planner, planner.params)  # (neutral ones decide nothing)
    digest = stable_id(world.digest, planner.spec.planner, params, robot.robot_id, seed,
                       settings, length=8)
    return f"{slug(world.name)}__{slug(planner.label)}__{slug(robot.label)}__s{seed}__{digest}"


def expand(suite: Suite) -> list[EpisodeJob]:
    """Every episode of ``suite``: worlds x parameter sets x robot variants x seeds, in that order."""
    jobs = []
    for world in suite.worlds:
        for planner in suite.planners:
            for robot in suite.robots:
                for seed in suite.seeds:
                    jobs.append(EpisodeJob(
                        job_id=job_id(world, planner, robot, seed, suite.settings),
                        world=world.spec, world_name=world.name, world_file=world.file,
                        label=planner.label, planner=planner.spec, params=planner.params,
                        params_id=planner.params_id, robot=robot.spec, robot_label=robot.label,
                        robot_id=robot.robot_id, seed=seed, settings=dict(suite.settings),
                        wall_s=suite.wall_s))
    return jobs


def with_world_files(jobs: Iterable[EpisodeJob], files: dict[str, str]) -> list[EpisodeJob]:
    """Jobs whose world has no file yet (generated) get ``files[world_name]``."""
    return [replace(j, world_file=files[j.world_name]) if j.world_file is None else j
            for j in jobs]


def describe(suite: Suite) -> dict[str, Any]:
    """The suite as expanded, for run.json (no world geometry)."""
    return {
        "name": suite.name,
        "description": suite.description,
        "file": suite.file,
        "cwd": suite.cwd,
        "data": suite.data,
        "worlds": {w.name: {"file": w.file, "source": w.source, "digest": w.digest}
                   for w in suite.worlds},
        "planners": {p.label: {"planner": p.spec.planner, "params": p.params,
                               "params_id": p.params_id} for p in suite.planners},
        "robots": {r.label: {"robot_id": r.robot_id,
                             "spec": r.spec.model_dump(mode="json")} for r in suite.robots},
        "seeds": list(suite.seeds),
        "settings": suite.settings,
        "protocol": protocol_of(settings := EpisodeSettings(**suite.settings)).rules(settings),
        "wall_s": suite.wall_s,
    }
