"""YAML files with line numbers, and pydantic validation that reports file, key path and line.

``load_yaml`` returns plain data plus a :class:`LineIndex` mapping each key path to the
1-based line where it stands, so a validation error can point at the exact line.
"""

from __future__ import annotations

import copy
import difflib
import math
import re
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


# Bounds on what one YAML file may make: a file is read in full before anything runs, so
# these keep a hostile or broken file from exhausting memory or the stack.
MAX_DEPTH = 100  # nested mappings/lists, aliases included
MAX_ALIAS_NODES = 1_000_000  # values that aliases (*name) may add by repeating an anchor
MAX_FILE_BYTES = 256 * 1024 * 1024  # a world of a million obstacles is ~60 MB

_PLAIN_SCALAR_TAGS = frozenset(f"tag:yaml.org,2002:{t}" for t in (
    "null", "bool", "int", "float", "str", "timestamp", "binary"))
_SEQ_TAG = "tag:yaml.org,2002:seq"
_MAP_TAG = "tag:yaml.org,2002:map"
_MERGE_TAG = "tag:yaml.org,2002:merge"
_NO_KEY = object()  # a mapping waiting for its next key
_MERGE = object()  # the merge key <<
_STR_TAG = "tag:yaml.org,2002:str"
_FLOAT_TAG = "tag:yaml.org,2002:float"
_SIMPLE_FLOAT = re.compile(r"[-+]?[0-9]+\.[0-9]*(?:[eE][-+][0-9]+)?\Z")  # float() reads it alike


def _too_deep() -> str:
    """The one message for nesting past :data:`MAX_DEPTH` (read when raised, like the bound)."""
    return f"nested deeper than {MAX_DEPTH} levels"


def _event_parser(text: str) -> Any:
    """libyaml's C parser when PyYAML has it (about 10x faster), else PyYAML's own."""
    cls = getattr(yaml, "CSafeLoader", None) or yaml.SafeLoader
    return cls(text)


@dataclass
class _Anchor:
    value: Any
    nodes: int  # values inside, aliases expanded
    depth: int  # nesting below it
    open: bool = True  # still being read: an alias to it would be recursive


class _Composer:
    """Plain data from YAML parser events, with key-path lines, in one iterative pass.

    PyYAML's own composer recurses per nesting level (libyaml's C composer overflows the C
    stack on deep input) and expands aliases without limit. This one reads events in a loop,
    refuses nesting deeper than :data:`MAX_DEPTH`, recursive aliases, aliases that would add
    more than :data:`MAX_ALIAS_NODES` values, and tags other than plain YAML types (no
    ``!!python/...``): every refusal is a :class:`SpecError` with the line.
    """

    def __init__(self, file: str, index: LineIndex) -> None:
        self.file, self.index = file, index
        self.constructor = yaml.SafeLoader("")  # resolves and builds scalars only
        self.anchors: dict[str, _Anchor] = {}
        self.alias_nodes = 0
        self._plain: dict[str, Any] = {}  # plain scalar text -> value (immutable values only)

    def error(self, problem: str, line: int, loc: Loc = ()) -> SpecError:
        return SpecError(problem, file=self.file, key_path=format_key_path(loc) if loc else "",
                         line=line)

    def scalar(self, event: Any, loc: Loc, key: Any = _NO_KEY) -> Any:
        """The value of a scalar event; ``loc`` (and ``key``, if given, appended to it) is
        where it stands, for messages."""
        tag = event.tag
        value = event.value
        plain = tag is None and event.implicit[0]
        if plain:  # most scalars: untagged and unquoted; same text, same value
            cached = self._plain.get(value, _NO_KEY)
            if cached is not _NO_KEY:
                return cached
        if tag is None or tag == "!":
            if not plain and event.implicit[1]:  # quoted: text
                return value
            tag = self.constructor.resolve(yaml.ScalarNode, value, event.implicit)
        if tag == _MERGE_TAG:
            return _MERGE
        if tag not in _PLAIN_SCALAR_TAGS:
            raise self.error(_tag_problem(tag), event.start_mark.line + 1, _at(loc, key))
        if tag == _STR_TAG:
            out: Any = value
        elif tag == _FLOAT_TAG and _SIMPLE_FLOAT.match(value):
            out = float(value)
        else:
            node = yaml.ScalarNode(tag, value, event.start_mark, event.end_mark, event.style)
            try:
                out = self.constructor.construct_object(node, deep=True)
            except Exception as exc:  # e.g. a timestamp like 2024-02-30, bad base64
                raise self.error(f"cannot read value {value!r:.40}: "
                                 f"{getattr(exc, 'problem', None) or exc}",
                                 event.start_mark.line + 1, _at(loc, key)) from None
        if isinstance(out, float) and not math.isfinite(out):
            raise self.error(f"expected a finite number, got {value}", event.start_mark.line + 1,
                             _at(loc, key))
        if plain and isinstance(out, (str, int, float, type(None))):  # immutable: shareable
            self._plain[value] = out
        return out

    def compose(self, parser: Any) -> Any:
        """The first document's data (None for an empty stream)."""
        scalar_event, alias_event = yaml.ScalarEvent, yaml.AliasEvent
        map_start, seq_start = yaml.MappingStartEvent, yaml.SequenceStartEvent
        ends = (yaml.MappingEndEvent, yaml.SequenceEndEvent)
        skipped = (yaml.StreamStartEvent, yaml.DocumentStartEvent)
        lines = self.index.lines
        # stack entries: [container, loc, is_map, pending_key, anchor, nodes, depth, merges]
        stack: list[list[Any]] = []
        parent: list[Any] | None = None  # stack[-1]
        result: Any = None
        documents = 0
        while True:
            event = parser.get_event()
            cls = type(event)
            if cls in ends:
                _, _, _, _, anchor, size, height, merges = entry = stack.pop()
                value = entry[0]
                for extra in merges:
                    for k, v in extra.items():
                        value.setdefault(k, v)
                height += 1
                if anchor is not None:
                    a = self.anchors[anchor]
                    a.value, a.nodes, a.depth, a.open = value, size, height, False
                line = event.start_mark.line + 1
                parent = stack[-1] if stack else None
            elif cls is scalar_event or cls is alias_event or cls is map_start or cls is seq_start:
                line = event.start_mark.line + 1
                if parent is not None and parent[2] and parent[3] is _NO_KEY:  # a mapping key
                    if cls is not scalar_event:
                        raise self.error("a mapping key must be a plain value (text or a "
                                         "number), not a list or mapping", line, parent[1])
                    key = self.scalar(event, parent[1])
                    if key is not _MERGE:
                        if key in parent[0]:
                            raise self.error(f"duplicate key {key!r}", line, (*parent[1], key))
                        lines[(*parent[1], key)] = line
                    parent[3] = key
                    continue
                if parent is None:
                    if documents:
                        raise self.error("expected a single document, found a second one", line)
                    loc: Loc = ()
                    lines.setdefault(loc, line)
                elif parent[2]:  # a mapping's value: its key's line is already recorded
                    if cls is scalar_event and event.anchor is None:  # the most common event
                        value, size, height = self.scalar(event, parent[1], parent[3]), 1, 0
                        parent[5] += 1
                        key, parent[3] = parent[3], _NO_KEY
                        if key is _MERGE:
                            raise self.error("a merge key (<<) takes a mapping or a list of "
                                             "mappings", line, parent[1])
                        parent[0][key] = value
                        continue
                    loc = (*parent[1], parent[3])
                else:
                    loc = (*parent[1], len(parent[0]))
                    lines.setdefault(loc, line)
                if cls is scalar_event:
                    value, size, height = self.scalar(event, loc), 1, 0
                    if event.anchor is not None:
                        self.anchors[event.anchor] = _Anchor(value, 1, 0, open=False)
                elif cls is alias_event:
                    value, size, height = self.alias(event, line, loc, len(stack))
                else:
                    is_map = cls is map_start
                    if event.tag not in (None, "!", _MAP_TAG if is_map else _SEQ_TAG):
                        raise self.error(_tag_problem(event.tag), line, loc)
                    if len(stack) >= MAX_DEPTH:
                        raise self.error(_too_deep(), line)
                    if event.anchor is not None:
                        self.anchors[event.anchor] = _Anchor(None, 0, 0)
                    parent = [{} if is_map else [], loc, is_map, _NO_KEY, event.anchor, 1, 0, []]
                    stack.append(parent)
                    continue
            elif event is None or cls is yaml.StreamEndEvent:
                break
            elif cls in skipped:
                continue
            else:  # the end of a document
                documents += 1
                continue
            if parent is None:  # the document's top-level value
                result = value
                continue
            parent[5] += size
            if height > parent[6]:
                parent[6] = height
            if parent[2]:
                key, parent[3] = parent[3], _NO_KEY
                if key is _MERGE:
                    merges = value if isinstance(value, list) else [value]
                    if not all(isinstance(m, dict) for m in merges):
                        raise self.error("a merge key (<<) takes a mapping or a list of "
                                         "mappings", line, parent[1])
                    parent[7].extend(merges)
                else:
                    parent[0][key] = value
            else:
                parent[0].append(value)
        return result

    def alias(self, event: Any, line: int, loc: Loc, depth: int) -> tuple[Any, int, int]:
        """A copy of an anchored value (its size and height), within the bounds."""
        anchor = self.anchors.get(event.anchor)
        if anchor is None:
            raise self.error(f"alias *{event.anchor} names no anchor", line, loc)
        if anchor.open:
            raise self.error(f"alias *{event.anchor} refers to a value that contains it "
                             f"(a recursive alias)", line, loc)
        self.alias_nodes += anchor.nodes
        if self.alias_nodes > MAX_ALIAS_NODES:
            raise self.error(f"aliases expand to more than {MAX_ALIAS_NODES:,} values "
                             f"(an alias bomb?)", line, loc)
        if depth + anchor.depth > MAX_DEPTH:
            raise self.error(_too_deep(), line)
        value = copy.deepcopy(anchor.value) if anchor.nodes > 1 else anchor.value
        return value, anchor.nodes, anchor.depth



def _at(loc: Loc, key: Any) -> Loc:
    return loc if key is _NO_KEY else (*loc, key)


def _tag_problem(tag: str) -> str:
    shown = tag.replace("tag:yaml.org,2002:", "!!")
    return (f"unsupported YAML tag {shown!r}: nav-bench reads plain YAML (mappings, lists, "
            f"numbers, text, true/false, null)")


def parse_yaml(text: str, file: str | Path = "<string>") -> tuple[Any, LineIndex]:
    """Parse one YAML document; syntax errors become :class:`SpecError` with the line."""
    file = str(file)
    index = LineIndex()
    try:
        data = _Composer(file, index).compose(_event_parser(text))
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark is not None else None
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        if "maximum nesting depth" in problem:
            # libyaml 0.2.6 (PyYAML >= 6.0.4) refuses flow nesting past 1000 levels while its
            # scanner reads ahead, before the composer sees depth MAX_DEPTH: one message either way
            raise SpecError(_too_deep(), file=file, line=line) from None
        raise SpecError(f"not valid YAML: {problem}", file=file, line=line) from None
    return data, index


def load_yaml(path: str | Path) -> tuple[Any, LineIndex]:
    """Read and parse a YAML file; a missing or unreadable file is a :class:`SpecError`."""
    path = Path(path)
    try:
        if path.stat().st_size > MAX_FILE_BYTES:
            raise SpecError(f"file is larger than {MAX_FILE_BYTES >> 20} MiB; not read",
                            file=path)
        raw = path.read_bytes()
    except OSError as exc:
        raise SpecError(f"cannot read file: {exc.strerror or exc}", file=path) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw.count(b"\n", 0, exc.start) + 1
        raise SpecError(f"not UTF-8 text (byte 0x{raw[exc.start]:02x}); is it a YAML file?",
                        file=path, line=line) from None
    return parse_yaml(text.removeprefix("\ufeff"), path)


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
        close = difflib.get_close_matches(str(loc[-1]) if loc else "", allowed, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        return f"unknown key; {hint}allowed here: {', '.join(allowed)}"
    if kind == "missing":
        return "required key is missing"
    if kind == "finite_number":
        return f"expected a finite number (got {err.get('input')!r})"
    if "input" in err and kind not in ("value_error", "assertion_error"):
        value = err["input"]
        shown = repr(value)
        if len(shown) > 60:
            shown = shown[:57] + "..."
        return f"{msg} (got {shown})"
    return msg.removeprefix("Value error, ")


def _clean_loc(loc: Sequence[str | int], data: Any = None) -> Loc:
    """``loc`` without the union-member and function-validator tags pydantic inserts; a part
    that is a key of the data at that point is the user's (even a key like ``s[onar``)."""
    out: list[str | int] = []
    node = data
    for p in loc:
        in_list = isinstance(node, list) and isinstance(p, int) and 0 <= p < len(node)
        if in_list or (isinstance(node, dict) and p in node):
            node = node[p]
        elif isinstance(p, str) and ("[" in p or p.startswith("function-")):
            continue
        else:
            node = None
        out.append(p)
    return tuple(out)


def validate(model: type[M], data: Any, *, file: str | Path | None, index: LineIndex | None,
             prefix: Loc = ()) -> M:
    """Validate ``data`` against ``model``; errors name file, key path and line, all at once."""
    try:
        return model.model_validate(data if data is not None else {})
    except ValidationError as exc:
        errors = []
        for err in exc.errors():
            own = _clean_loc(err["loc"], data)
            loc = (*prefix, *own)
            line = index.line_of(loc) if index else None
            errors.append(SpecError(_describe(err, model, own), file=file, key_path=format_key_path(loc), line=line))
        if len(errors) == 1:
            raise errors[0] from None
        raise SpecErrors(errors) from None
