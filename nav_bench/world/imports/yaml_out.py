"""Write world data as plain, readable YAML: block style, flow style for shapes and pairs."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import yaml

# mappings made only of these keys are shapes: written on one line, {center: [1, 2], ...}
SHAPE_KEYS = frozenset({"center", "size", "radius", "yaw_deg", "from", "to", "thickness",
                        "points", "closed"})


class _WorldDumper(yaml.SafeDumper):
    """Lists of scalars (and of pairs) and shape mappings in flow style; the rest in block."""


def _is_scalar(v: Any) -> bool:
    return isinstance(v, (int, float, str, bool)) or v is None


def _represent_list(dumper: yaml.SafeDumper, data: list) -> yaml.Node:
    flat = all(_is_scalar(v) or (isinstance(v, (list, tuple)) and all(map(_is_scalar, v)))
               for v in data)
    return dumper.represent_sequence("tag:yaml.org,2002:seq", data, flow_style=bool(data) and flat)


def _represent_dict(dumper: yaml.SafeDumper, data: dict) -> yaml.Node:
    flow = bool(data) and set(data) <= SHAPE_KEYS
    return dumper.represent_mapping("tag:yaml.org,2002:map", data.items(), flow_style=flow)


_WorldDumper.add_representer(list, _represent_list)
_WorldDumper.add_representer(tuple, _represent_list)
_WorldDumper.add_representer(dict, _represent_dict)
_WorldDumper.add_multi_representer(np.floating, lambda d, v: d.represent_float(float(v)))
_WorldDumper.add_multi_representer(np.integer, lambda d, v: d.represent_int(int(v)))
_WorldDumper.add_multi_representer(np.bool_, lambda d, v: d.represent_bool(bool(v)))


def header_lines(data: dict[str, Any]) -> list[str]:
    """Comment lines naming the source and licence recorded in ``data['meta']``."""
    meta = data.get("meta") or {}
    lines = [f"nav-bench world: {data.get('name') or 'imported'}"]
    for key, label in (("source", "source"), ("licence", "licence"), ("imported_by", "made by")):
        if meta.get(key):
            lines.append(f"{label}: {meta[key]}")
    return lines


def dump_world_yaml(data: dict[str, Any], header: list[str] | None = None) -> str:
    """The YAML text of world ``data`` with a ``#`` comment header (default: from ``meta``)."""
    lines = header_lines(data) if header is None else header
    body = yaml.dump(data, Dumper=_WorldDumper, sort_keys=False, allow_unicode=True, width=100,
                     default_flow_style=False)
    return "".join(f"# {line}\n" for line in lines) + body


def write_world_yaml(data: dict[str, Any], path: str | Path, header: list[str] | None = None) -> Path:
    """Write world ``data`` to ``path`` (parent folders created) and return the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(dump_world_yaml(data, header), encoding="utf-8")
    return path
