"""Planner registry: names -> planner classes, with "did you mean" errors.

Three ways in: the built-in planners below, the entry-point group
``nav_bench.planners`` of installed packages, and a dotted path
``package.module:ClassName`` given wherever a planner name is accepted.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import sys
from collections.abc import Iterator
from importlib.metadata import entry_points
from pathlib import Path
from typing import Any

import yaml

from nav_bench.errors import InputError, SpecError, UnknownNameError
from nav_bench.ids import params_id
from nav_bench.paths import find, shipped
from nav_bench.planners.base import ParamError, Planner, resolve_params
from nav_bench.specs import PlannerSetSpec
from nav_bench.yamlio import LineIndex, load_yaml, validate

ENTRY_POINT_GROUP = "nav_bench.planners"

# name -> "module:Class"; imported only when asked for, so one broken planner breaks only itself
BUILTIN: dict[str, str] = {
    "goal_seek": "nav_bench.planners.goal_seek:GoalSeek",
    "eopc": "nav_bench.planners.eopc:EOPC",
    "bug2": "nav_bench.planners.bug2:Bug2",
    "tangent_bug": "nav_bench.planners.tangent_bug:TangentBug",
    "dstar_lite": "nav_bench.planners.dstar_lite:DStarLite",
    "vfh_plus": "nav_bench.planners.vfh_plus:VFHPlus",
    "apf": "nav_bench.planners.apf:PotentialField",
    "dwa": "nav_bench.planners.dwa:DWA",
    "dwa_global": "nav_bench.planners.dwa:DWAGlobal",
    "policy": "nav_bench.planners.policy:PolicyPlanner",
}


class PlannerRegistry:
    """A name -> class mapping. Registering a taken name is an error."""

    def __init__(self, builtin: dict[str, str] | None = None, use_entry_points: bool = True) -> None:
        self._targets: dict[str, str | type[Planner]] = {}
        for name, target in (builtin or {}).items():
            module = target.split(":")[0]
            if importlib.util.find_spec(module) is not None:
                self._targets[name] = target
        if use_entry_points:
            for ep in entry_points(group=ENTRY_POINT_GROUP):
                self.register(ep.name, ep.value)

    def register(self, name: str, target: str | type[Planner]) -> None:
        """Add ``name``; ``target`` is a class or a ``module:Class`` string."""
        if name in self._targets:
            raise InputError(f"planner name {name!r} is registered twice "
                             f"({self._targets[name]!r} and {target!r})")
        self._targets[name] = target

    def names(self) -> list[str]:
        return sorted(self._targets)

    def __contains__(self, name: str) -> bool:
        return name in self._targets

    def __iter__(self) -> Iterator[str]:
        return iter(self.names())

    def get(self, name: str) -> type[Planner]:
        """The class for a registered name or a ``module:Class`` dotted path."""
        if name in self._targets:
            target = self._targets[name]
        elif ":" in name:  # a dotted path "package.module:Class"
            target = name
        else:
            raise UnknownNameError("planner", name, self.names())
        cls = load_dotted(target) if isinstance(target, str) else target
        if not (isinstance(cls, type) and issubclass(cls, Planner)):
            raise InputError(f"{target!r} is not a nav_bench Planner subclass")
        return cls


def _import_user_module(module_name: str) -> Any:
    """Import a user's module; whatever its code raises becomes one :class:`InputError` line
    naming the module, the exception and the line of the user's file that raised it."""
    try:
        return importlib.import_module(module_name)
    except ImportError:
        raise
    except Exception as exc:  # the user's module ran and raised: name where
        import traceback

        frames = traceback.extract_tb(exc.__traceback__)
        user = [f for f in frames if "importlib" not in f.filename]
        where = f" at {user[-1].filename}:{user[-1].lineno}" if user else ""
        raise InputError(f"planner module {module_name!r} raised on import{where}: "
                         f"{type(exc).__name__}: {exc}") from None


def load_dotted(target: str) -> Any:
    """Import ``package.module:Attribute``."""
    module_name, _, attr = target.partition(":")
    if not attr or not module_name:
        raise InputError(f"expected 'package.module:ClassName', got {target!r}")
    try:
        module = _import_user_module(module_name)
    except ImportError as exc:
        # the `nav-bench` script does not put the working folder on sys.path (python -m does);
        # a user's planner module next to their suite should load either way
        cwd = os.getcwd()
        if cwd in sys.path:
            raise InputError(f"cannot import planner module {module_name!r}: {exc}") from None
        sys.path.append(cwd)
        try:
            module = _import_user_module(module_name)
        except ImportError as exc2:
            raise InputError(f"cannot import planner module {module_name!r}: {exc2}") from None
    try:
        return getattr(module, attr)
    except AttributeError:
        raise InputError(f"module {module_name!r} has no attribute {attr!r}") from None


_default: PlannerRegistry | None = None


def default_registry() -> PlannerRegistry:
    """The registry of built-in and entry-point planners (built once per process, then read-only)."""
    global _default
    if _default is None:
        _default = PlannerRegistry(BUILTIN)
    return _default


def check_params(planner: str, params: dict[str, Any], *, file: str | Path | None = None,
                 index: LineIndex | None = None, registry: PlannerRegistry | None = None) -> dict[str, Any]:
    """Full parameter dict for ``planner``; errors name the file, ``params.<key>`` and its line."""
    registry = registry or default_registry()
    try:
        cls = registry.get(planner)
    except InputError as exc:
        raise SpecError(str(exc), file=file, key_path="planner",
                        line=index.line_of(("planner",)) if index else None) from None
    try:
        return resolve_params(cls, params)
    except ParamError as exc:
        loc = ("params", exc.param)
        raise SpecError(str(exc), file=file, key_path=".".join(map(str, loc)),
                        line=index.line_of(loc) if index else None) from None


def load_planner_set(path: str | Path) -> PlannerSetSpec:
    """Read a planner parameter-set file. Parameter names are checked by the registry."""
    data, index = load_yaml(path)
    spec = validate(PlannerSetSpec, data, file=path, index=index)
    check_params(spec.planner, spec.params, file=path, index=index)
    return spec


def parse_planner_arg(text: str) -> PlannerSetSpec:
    """A CLI/suite planner reference as a parameter set.

    ``eopc`` (a name), ``configs/planners/eopc_paper.yaml`` (a file),
    ``eopc:RR=0.4,lambda1=0.9`` (name with overrides), ``pkg.mod:Cls`` (a dotted path).
    """
    if text.endswith((".yaml", ".yml")):
        return load_planner_set(find("planner set", text).path)
    name, overrides = text, {}
    head, sep, tail = text.rpartition(":")
    if sep and ("=" in tail or head in default_registry()):
        name = head
        for item in tail.split(","):
            key, eq, value = item.partition("=")
            if not eq or not key.strip():
                raise InputError(f"planner override {item!r} in {text!r} is not key=value")
            overrides[key.strip()] = yaml.safe_load(value)
    set_file = _planner_set_file(name)
    if set_file is not None:
        base = load_planner_set(set_file)
        spec = PlannerSetSpec(planner=base.planner, params={**base.params, **overrides})
    else:
        spec = PlannerSetSpec(planner=name, params=overrides)
    resolve_params(default_registry().get(spec.planner), spec.params)
    return spec


def _planner_set_file(name: str) -> Path | None:
    """The parameter-set file ``name`` refers to: a path, or a shipped set's name
    (``eopc_paper``) that is not a registered planner; None for a planner."""
    if name.endswith((".yaml", ".yml")):
        return find("planner set", name).path
    registry = default_registry()
    if name in registry or ":" in name:
        return None
    sets = shipped("planner set")
    if name in sets:
        return sets[name]
    raise UnknownNameError("planner or parameter set", name, [*registry.names(), *sets])


def make_planner(spec: PlannerSetSpec, registry: PlannerRegistry | None = None) -> Planner:
    """Instantiate the planner of a parameter set."""
    cls = (registry or default_registry()).get(spec.planner)
    return cls(**spec.params)


def full_params(spec: PlannerSetSpec, registry: PlannerRegistry | None = None) -> dict[str, Any]:
    """The parameter set with every default filled in (what the result row records)."""
    cls = (registry or default_registry()).get(spec.planner)
    return resolve_params(cls, spec.params)


def identity_params(planner: str, params: dict[str, Any],
                    registry: PlannerRegistry | None = None) -> dict[str, Any]:
    """``params`` without the planner's neutral parameters (:attr:`Param.neutral`: they change
    how it computes, not what): the part the ids of a parameter set and of its jobs hash, so
    that adding or changing one changes no episode's id or random stream."""
    cls = (registry or default_registry()).get(planner)
    neutral = {p.name for p in cls.params if p.neutral}
    return {k: v for k, v in params.items() if k not in neutral}


def set_id(planner: str, params: dict[str, Any], registry: PlannerRegistry | None = None) -> str:
    """The id of a full parameter set (:func:`~nav_bench.ids.params_id`) of its
    :func:`identity_params`."""
    return params_id(planner, identity_params(planner, params, registry))
