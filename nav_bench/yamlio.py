"""YAML files with line numbers, and pydantic validation that reports file, key path and line.

``load_yaml`` returns plain data plus a :class:`LineIndex` mapping each key path to the
1-based line where it stands, so a validation error can point at the exact line.
"""

from __future__ import annotations

import difflib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar, get_args

import yaml
from pydantic import BaseModel, ValidationError

from nav_bench.errors import SpecError, SpecErrors, format_key_path

Loc = tuple[str | int, ...]
M = TypeVar("M", bound=BaseModel)


@dataclass
class LineIndex:
    """Key path -> 1-based line, for one YAML document."""

    lines: dict[Loc, int] = field(default_factory=dict)

    def line_of(self, loc: Sequence[str | int]) -> int | None:
        """The line of ``loc`` or of its nearest ancestor that has one."""
        loc = tuple(loc)
        while True:
            if loc in self.lines:
                return self.lines[loc]
            if not loc:
                return None
            loc = loc[:-1]


def _construct(node: yaml.Node, loc: Loc, index: LineIndex, file: str,
               loader: yaml.SafeLoader) -> Any:
    index.lines.setdefault(loc, node.start_mark.line + 1)
    if isinstance(node, yaml.MappingNode):
        out: dict[Any, Any] = {}
        for key_node, value_node in node.value:
            key = loader.construct_object(key_node, deep=True)
            if isinstance(key, list):
                key = tuple(key)
            if key in out:
                raise SpecError(f"duplicate key {key!r}", file=file,
                                key_path=format_key_path((*loc, key)), line=key_node.start_mark.line + 1)
            index.lines[(*loc, key)] = key_node.start_mark.line + 1
            out[key] = _construct(value_node, (*loc, key), index, file, loader)
        return out
    if isinstance(node, yaml.SequenceNode):
        return [_construct(v, (*loc, i), index, file, loader) for i, v in enumerate(node.value)]
    return loader.construct_object(node, deep=True)


def parse_yaml(text: str, file: str | Path = "<string>") -> tuple[Any, LineIndex]:
    """Parse one YAML document; syntax errors become :class:`SpecError` with the line."""
    file = str(file)
    try:
        node = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark is not None else None
        problem = getattr(exc, "problem", None) or str(exc)
        raise SpecError(f"not valid YAML: {problem}", file=file, line=line) from None
    index = LineIndex()
    if node is None:
        return None, index
    loader = yaml.SafeLoader("")
    try:
        return _construct(node, (), index, file, loader), index
    finally:
        loader.dispose()


def load_yaml(path: str | Path) -> tuple[Any, LineIndex]:
    """Read and parse a YAML file; a missing or unreadable file is a :class:`SpecError`."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise SpecError(f"cannot read file: {exc.strerror or exc}", file=path) from None
    return parse_yaml(text, path)


def _model_at(model: type[BaseModel], loc: Sequence[str | int]) -> type[BaseModel] | None:
    """The pydantic model that validates the mapping at ``loc`` (None if not a model)."""
    current: Any = model
    for part in loc:
        if isinstance(part, int):
            continue
        if not (isinstance(current, type) and issubclass(current, BaseModel)):
            return None
        fields = {f.alias or name: f for name, f in current.model_fields.items()}
        if part not in fields:
            return None
        current = _first_model(fields[part].annotation)
    return current if isinstance(current, type) and issubclass(current, BaseModel) else None


def _first_model(annotation: Any) -> Any:
    """The first BaseModel inside ``X | None``, ``list[X]``, ``dict[str, X]`` and the like."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in get_args(annotation):
        found = _first_model(arg)
        if found is not None:
            return found
    return None


def _describe(err: dict[str, Any], model: type[BaseModel], loc: Loc) -> str:
    kind = err.get("type", "")
    msg = err.get("msg", "invalid value")
    if kind == "extra_forbidden":
        parent = _model_at(model, loc[:-1])
        if parent is None:
            return "unknown key"
        allowed = sorted(f.alias or name for name, f in parent.model_fields.items()
                         if name != "base_dir")
        close = difflib.get_close_matches(str(loc[-1]), allowed, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        return f"unknown key; {hint}allowed here: {', '.join(allowed)}"
    if kind == "missing":
        return "required key is missing"
    if "input" in err and kind not in ("value_error", "assertion_error"):
        value = err["input"]
        shown = repr(value)
        if len(shown) > 60:
            shown = shown[:57] + "..."
        return f"{msg} (got {shown})"
    return msg.removeprefix("Value error, ")


def _clean_loc(loc: Sequence[str | int]) -> Loc:
    # pydantic inserts union-member and function-validator tags into locations; drop them
    return tuple(p for p in loc if not (isinstance(p, str) and ("[" in p or p.startswith("function-"))))


def validate(model: type[M], data: Any, *, file: str | Path | None, index: LineIndex | None,
             prefix: Loc = ()) -> M:
    """Validate ``data`` against ``model``; errors name file, key path and line, all at once."""
    try:
        return model.model_validate(data if data is not None else {})
    except ValidationError as exc:
        errors = []
        for err in exc.errors():
            own = _clean_loc(err["loc"])
            loc = (*prefix, *own)
            line = index.line_of(loc) if index else None
            errors.append(SpecError(_describe(err, model, own), file=file, key_path=format_key_path(loc), line=line))
        if len(errors) == 1:
            raise errors[0] from None
        raise SpecErrors(errors) from None
