"""Where the shipped data folders (worlds/, robots/, configs/) are, and files by name.

The top-level folders of the repository are the source of truth. A wheel carries a copy of
them as package data (``nav_bench/data/``, copied at build time by ``setup.py``), found here
through :mod:`importlib.resources`; a source checkout uses the folders themselves.

A file is looked up, first to last:

1. as a path (absolute, or relative to the working folder): a user's own file always wins;
2. relative to each project root (``$NAV_BENCH_HOME``, the working folder, the shipped data),
   as a path (``worlds/paper/open_room.yaml``) or as a name inside its kind's folder
   (``paper/open_room`` -> ``worlds/paper/open_room.yaml``, ``smoke`` ->
   ``configs/suites/smoke.yaml``);
3. as a bare file stem when exactly one file of that kind has it (``open_room``).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from nav_bench.errors import InputError, UnknownNameError

DATA_FOLDERS = ("worlds", "robots", "configs")
_SOURCE_ROOT = Path(__file__).resolve().parent.parent
_YAML = (".yaml", ".yml")

# kind -> its folder below a project root
KIND_FOLDERS: dict[str, str] = {
    "suite": "configs/suites",
    "world": "worlds",
    "planner set": "configs/planners",
    "robot": "robots",
}


def source_root() -> Path:
    """The folder above the ``nav_bench`` package: a source checkout's repository root (in an
    installed wheel, ``site-packages``)."""
    return _SOURCE_ROOT


def data_root() -> Path:
    """The folder holding the shipped ``worlds/``, ``robots/`` and ``configs/``.

    An installed wheel: its package data ``nav_bench/data``. A source checkout (editable
    install included): the repository, where the folders are the source of truth.
    """
    packaged = resources.files("nav_bench").joinpath("data")
    if packaged.is_dir():
        return Path(str(packaged))
    return _SOURCE_ROOT


def project_roots() -> list[Path]:
    """Roots searched for relative paths, first wins: $NAV_BENCH_HOME, the working folder,
    the shipped data."""
    roots = []
    if os.environ.get("NAV_BENCH_HOME"):
        roots.append(Path(os.environ["NAV_BENCH_HOME"]))
    roots += [Path.cwd(), data_root()]
    return list(dict.fromkeys(roots))


def project_file(relative: str | Path) -> Path:
    """The first existing ``root/relative``; the shipped path if none exists."""
    for root in project_roots():
        candidate = root / relative
        if candidate.exists():
            return candidate
    return data_root() / relative


@dataclass(frozen=True)
class Found:
    """A file found by :func:`find`.

    Attributes:
        path: where it is (absolute).
        given: how results record it: the user's path as typed, or, for a file found below a
            project root, its path relative to that root (``worlds/paper/open_room.yaml``), the
            same whether nav-bench runs from a checkout or from an installed wheel.
    """

    path: Path
    given: str


def _names_below(root: Path, folder: str) -> dict[str, Path]:
    base = root / folder
    if not base.is_dir():
        return {}
    return {p.relative_to(base).with_suffix("").as_posix(): p
            for p in sorted(base.rglob("*")) if p.suffix in _YAML and p.is_file()}


def shipped(kind: str) -> dict[str, Path]:
    """Name -> file of every ``kind`` file below the project roots (a nearer root's file
    hides a shipped one of the same name)."""
    folder = KIND_FOLDERS[kind]
    out: dict[str, Path] = {}
    for root in reversed(project_roots()):
        out.update(_names_below(root, folder))
    return dict(sorted(out.items()))


def find(kind: str, text: str | Path) -> Found:
    """The file of kind ``kind`` ("world", "suite", "planner set", "robot") that ``text``
    names: a path, a path below a project root, or a name (see the module's doc)."""
    text = str(text)
    path = Path(text).expanduser()
    if path.is_file():
        return Found(path.resolve(), text)
    folder = KIND_FOLDERS[kind]
    tries = [text] if path.is_absolute() else [text, f"{folder}/{text}"]
    if path.suffix not in _YAML:
        tries += [t + ext for t in tries for ext in _YAML]
    for root in project_roots():
        for rel in tries:
            if (root / rel).is_file():
                return Found((root / rel).resolve(), Path(rel).as_posix())
    known = shipped(kind)
    stem = path.with_suffix("").name if path.suffix in _YAML else path.name
    by_stem = sorted(name for name in known if name.rsplit("/", 1)[-1] == stem)
    if len(by_stem) == 1 and not path.is_absolute() and "/" not in text:
        file = known[by_stem[0]]
        return Found(file.resolve(), f"{folder}/{by_stem[0]}{file.suffix}")
    if len(by_stem) > 1:
        raise InputError(f"{kind} {text!r} is ambiguous: {', '.join(by_stem)}")
    raise UnknownNameError(f"{kind} (a file, or a name from `nav-bench list`)", text, known)


def describe(kind: str) -> list[tuple[str, str]]:
    """(name, one line about it) for every ``kind`` file below the project roots."""
    import yaml

    out = []
    for name, file in shipped(kind).items():
        try:
            data = yaml.safe_load(file.read_text(encoding="utf-8")) or {}
        except (OSError, yaml.YAMLError) as exc:
            out.append((name, f"(unreadable: {exc.__class__.__name__})"))
            continue
        data = data if isinstance(data, dict) else {}
        if kind == "planner set":
            line = f"{data.get('planner', '?')} {data.get('params') or {}}"
        else:
            line = str(data.get("description") or "")
        if not line:  # the file's first comment
            comments = [t.lstrip("# ").strip() for t in file.read_text(encoding="utf-8")
                        .splitlines() if t.startswith("#")]
            line = comments[0] if comments else ""
        out.append((name, " ".join(line.split())))
    return out
