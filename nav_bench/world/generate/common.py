"""Shared pieces of the world generators: settings, seeding, walls on grids, YAML output.

* :class:`Setting` / :func:`resolve_settings`: every generator setting has a default, a unit,
  one line of meaning and a range; user values (YAML scalars, ``"8,8"`` strings from the
  command line) are converted and checked, unknown names get a did-you-mean.
* :func:`attempt_rng`: the random generator of one attempt, derived from (kind, seed, attempt)
  through ``numpy.random.SeedSequence`` (platform independent).
* :func:`merge_runs`: runs of wall edges along grid lines, merged into long walls.
* :func:`clean_world_data` / :func:`world_yaml_text` / :func:`write_world_yaml`: plain data,
  coordinates rounded to millimetres, written in a fixed key order and float format (by the
  importers' YAML writer, shared) so the same inputs give the same bytes on any machine.

Units: metres, degrees only where a key says ``_deg``.
"""

from __future__ import annotations

import contextlib
import difflib
import math
import zlib
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import yaml

from nav_bench.errors import InputError
from nav_bench.specs import default_robot_radius

DECIMALS = 3  # coordinates are written to the millimetre
DEFAULT_ROBOT_RADIUS = default_robot_radius()  # m, read from the default robot's URDF


# --------------------------------------------------------------------------- settings
class Setting(NamedTuple):
    """One generator setting. Indexable as ``(name, default, unit, doc)`` first.

    The type is the default's: ``bool``, ``int``, ``float``, ``str`` (then ``choices``), or a
    pair ``(a, b)`` of ints or floats (``minimum``/``maximum`` apply to both; ``ordered``
    requires ``a <= b``, for ranges). ``positive`` makes ``minimum`` exclusive.
    """

    name: str
    default: Any
    unit: str
    doc: str
    minimum: float | None = None
    maximum: float | None = None
    choices: tuple[str, ...] | None = None
    ordered: bool = False
    positive: bool = False

    def check(self, value: Any, where: str) -> Any:
        """``value`` converted to this setting's type, or :class:`InputError` naming it."""
        name = f"{where} setting {self.name!r}"
        if isinstance(self.default, tuple):
            return self._check_pair(value, name)
        return self._check_scalar(value, name, self.default)

    def _check_pair(self, value: Any, name: str) -> tuple[Any, Any]:
        if isinstance(value, str):  # "8,8" or "[8, 8]" from the command line
            text = value.strip()
            value = yaml.safe_load(text if text.startswith("[") else f"[{text}]")
        if not isinstance(value, (list, tuple)) or len(value) != 2:
            raise InputError(f"{name} expects two numbers like {_fmt(self.default)}, got {value!r}")
        pair = tuple(self._check_scalar(v, name, self.default[0]) for v in value)
        if self.ordered and pair[0] > pair[1]:
            raise InputError(f"{name} is a range [low, high]; got low > high: {list(pair)}")
        return pair  # type: ignore[return-value]

    def _check_scalar(self, value: Any, name: str, like: Any) -> Any:
        expected = type(like)
        if isinstance(value, str) and expected is not str:
            with contextlib.suppress(yaml.YAMLError):  # not YAML: reported as the wrong type
                value = yaml.safe_load(value)
        if expected is bool:
            if not isinstance(value, bool):
                raise InputError(f"{name} expects true or false, got {value!r}")
            return value
        if expected is str:
            if not isinstance(value, str):
                raise InputError(f"{name} expects text, got {value!r}")
            if self.choices is not None and value not in self.choices:
                close = difflib.get_close_matches(value, self.choices, n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                raise InputError(f"{name} must be one of {list(self.choices)}, got {value!r}{hint}")
            return value
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            unit = f" in {self.unit}" if self.unit else ""
            raise InputError(f"{name} expects a number{unit}, got {value!r}")
        if expected is int:
            if float(value) != int(value):
                raise InputError(f"{name} expects a whole number, got {value!r}")
            value = int(value)
        else:
            value = float(value)
        unit = f" {self.unit}" if self.unit and self.unit != "-" else ""
        if self.minimum is not None:
            if self.positive and value <= self.minimum:
                raise InputError(f"{name} must be > {self.minimum:g}{unit}, got {value!r}")
            if value < self.minimum:
                raise InputError(f"{name} must be >= {self.minimum:g}{unit}, got {value!r}")
        if self.maximum is not None and value > self.maximum:
            raise InputError(f"{name} must be <= {self.maximum:g}{unit}, got {value!r}")
        return value


def _fmt(value: Any) -> str:
    return f"[{value[0]}, {value[1]}]" if isinstance(value, tuple) else repr(value)


#: Settings every generator accepts (appended after the family's own settings).
COMMON_SETTINGS: tuple[Setting, ...] = (
    Setting("robot_radius", DEFAULT_ROBOT_RADIUS, "m",
            "the goal is guaranteed reachable for a disc robot of this radius", 0.0, 2.0,
            positive=True),
    Setting("max_attempts", 50, "-",
            "layouts tried (with derived seeds) before giving up on a reachable goal", 1, 10000),
    Setting("movers", 0, "-", "moving obstacles added on free straight paths (see movers.py)",
            0, 100),
    Setting("mover_speed", (0.2, 0.5), "m/s", "range of mover speeds", 0.0, 5.0,
            ordered=True, positive=True),
    Setting("mover_radius", 0.2, "m", "radius of each (cylindrical) mover", 0.0, 2.0,
            positive=True),
    Setting("mover_mode", "pingpong", "-", "pingpong: back and forth on a segment; "
            "loop: round an axis-aligned rectangle", choices=("pingpong", "loop")),
    Setting("mover_length", (1.5, 4.0), "m", "range of a mover's segment length (loop: of "
            "its rectangle's half perimeter)", 0.0, 100.0, ordered=True, positive=True),
)


@dataclass(frozen=True)
class GeneratorInfo:
    """A registered generator.

    Attributes:
        name: the kind users type (``maze``).
        doc: one paragraph on what it builds.
        settings: family settings then :data:`COMMON_SETTINGS`; each ``(name, default, unit, doc)``.
        build: ``build(rng, settings) -> world data`` (no movers, no meta; may raise InputError).
    """

    name: str
    doc: str
    settings: tuple[Setting, ...]
    build: Callable[[np.random.Generator, dict[str, Any]], dict[str, Any]] = field(repr=False)


def make_info(name: str, doc: str, settings: Sequence[Setting],
              build: Callable[[np.random.Generator, dict[str, Any]], dict[str, Any]]) -> GeneratorInfo:
    """A :class:`GeneratorInfo` with the common settings appended."""
    names = [s.name for s in settings] + [s.name for s in COMMON_SETTINGS]
    assert len(set(names)) == len(names), f"duplicate setting names in {name}"
    return GeneratorInfo(name, doc, (*settings, *COMMON_SETTINGS), build)


def resolve_settings(info: GeneratorInfo, given: dict[str, Any] | None) -> dict[str, Any]:
    """All settings of ``info`` in declaration order: defaults updated by checked ``given``."""
    given = dict(given or {})
    known = {s.name: s for s in info.settings}
    for key in given:
        if key not in known:
            close = difflib.get_close_matches(str(key), list(known), n=1)
            hint = f" Did you mean {close[0]!r}?" if close else ""
            raise InputError(f"generator {info.name!r} has no setting {key!r}.{hint} "
                             f"Settings: {', '.join(known)}")
    return {name: (s.check(given[name], info.name) if name in given else s.default)
            for name, s in known.items()}


# --------------------------------------------------------------------------- seeding
def derived_seed(kind: str, seed: int, attempt: int) -> int:
    """The 64-bit seed of one attempt: a hash of (seed, attempt, kind) by ``SeedSequence``."""
    ss = np.random.SeedSequence([seed, attempt, zlib.crc32(kind.encode())])
    return int(ss.generate_state(1, np.uint64)[0])


def attempt_rng(kind: str, seed: int, attempt: int) -> np.random.Generator:
    """The random generator of one attempt (see :func:`derived_seed`)."""
    return np.random.default_rng(derived_seed(kind, seed, attempt))


def unit_vector(rng: np.random.Generator) -> np.ndarray:
    """A uniformly distributed direction (2,), by rejection: no trigonometry, so the same
    bits on every machine (sqrt and division are exactly rounded in IEEE 754)."""
    while True:
        x, y = (float(v) for v in rng.uniform(-1.0, 1.0, 2))
        n = math.sqrt(x * x + y * y)
        if 0.1 < n <= 1.0:
            return np.array([x / n, y / n])


# --------------------------------------------------------------------------- walls on a grid
def merge_runs(mask: np.ndarray) -> list[tuple[int, int, int]]:
    """Runs of True in each row of a 2-D bool array: ``(row, first, last)`` (inclusive)."""
    runs = []
    m = np.asarray(mask, dtype=bool)
    for r in range(m.shape[0]):
        padded = np.concatenate([[False], m[r], [False]]).astype(np.int8)
        edges = np.flatnonzero(np.diff(padded))
        runs += [(r, int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2], strict=True)]
    return runs


# --------------------------------------------------------------------------- plain data + YAML
def _clean(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_clean(v) for v in value]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return round(float(value), DECIMALS) + 0.0  # + 0.0 turns -0.0 into 0.0
    return value


def clean_world_data(data: dict[str, Any]) -> dict[str, Any]:
    """Plain Python data (lists, ints, floats rounded to :data:`DECIMALS`), same key order."""
    return _clean(data)


_TOP_ORDER = ("name", "description", "size", "boundary", "wall_height", "start", "goal",
              "obstacles", "movers", "meta")


def world_yaml_text(data: dict[str, Any], header: list[str] | None = None) -> str:
    """World data as YAML text, the same for the same data on any machine.

    Cleaned by :func:`clean_world_data`, top-level keys in a fixed order, written by the
    project's world writer (:func:`nav_bench.world.imports.yaml_out.dump_world_yaml`: one
    shape per line, Python's shortest round-trip float form). ``header`` comment lines
    default to the command that regenerates a generated world (else the writer's own).
    """
    from nav_bench.world.imports.yaml_out import dump_world_yaml

    data = clean_world_data(data)
    keys = [k for k in _TOP_ORDER if k in data] + [k for k in data if k not in _TOP_ORDER]
    return dump_world_yaml({k: data[k] for k in keys},
                           header if header is not None else regenerate_comment(data))


def write_world_yaml(data: dict[str, Any], path: str | Path, header: list[str] | None = None) -> Path:
    """Write :func:`world_yaml_text` to ``path`` (folders created) as UTF-8 with ``\\n`` line
    ends on every platform (byte-identical files); returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(world_yaml_text(data, header).encode("utf-8"))
    return path


def regenerate_comment(data: dict[str, Any]) -> list[str] | None:
    """``Generated by: nav-bench generate KIND --seed N --set k=v`` (non-default settings) for
    a generated world; ``None`` for any other."""
    gen = (data.get("meta") or {}).get("generator")
    if not isinstance(gen, dict) or "kind" not in gen:
        return None
    from nav_bench.world.generate import list_generators  # the registry knows the defaults

    info = list_generators().get(gen["kind"])
    defaults = {s.name: _clean(s.default) for s in info.settings} if info else {}
    parts = [f"nav-bench generate {gen['kind']} --seed {gen.get('seed', 0)}"]
    for key, value in (gen.get("settings") or {}).items():
        if defaults.get(key) != _clean(value):
            shown = ",".join(str(v) for v in value) if isinstance(value, (list, tuple)) else value
            if isinstance(shown, bool):
                shown = str(shown).lower()
            parts.append(f"--set {key}={shown}")
    return ["Generated by: " + " ".join(parts), "Regenerate rather than edit by hand."]


def primitive_count(obstacles: Iterable[dict[str, Any]]) -> int:
    """Number of primitive boxes/cylinders the obstacles turn into (a polyline counts its
    segments): the figure that drives simulation cost."""
    n = 0
    for ob in obstacles:
        if "polyline" in ob:
            pts = ob["polyline"]["points"]
            n += len(pts) - 1 + (1 if ob["polyline"].get("closed") else 0)
        else:
            n += 1
    return n
