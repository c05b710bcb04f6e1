"""Where the project's data folders (robots/, worlds/, configs/) are found."""

from __future__ import annotations

import os
from pathlib import Path

_PACKAGE_PARENT = Path(__file__).resolve().parent.parent


def project_roots() -> list[Path]:
    """Candidate roots, most specific first: $NAV_BENCH_HOME, the working folder, the source tree."""
    roots = []
    if os.environ.get("NAV_BENCH_HOME"):
        roots.append(Path(os.environ["NAV_BENCH_HOME"]))
    roots += [Path.cwd(), _PACKAGE_PARENT]
    return roots


def project_file(relative: str | Path) -> Path:
    """The first existing ``root/relative``; the source-tree path if none exists."""
    for root in project_roots():
        candidate = root / relative
        if candidate.exists():
            return candidate
    return _PACKAGE_PARENT / relative
