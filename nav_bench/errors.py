"""One exception family: every failure a user can see is a :class:`NavBenchError`.

``InputError`` and its subclasses mean *bad input, nothing simulated* and map to exit
status 2 on the command line; everything else maps to exit status 1.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from pathlib import Path


class NavBenchError(Exception):
    """Base of every error nav-bench raises on purpose."""

    exit_code = 1


class InputError(NavBenchError):
    """Bad input (a file, a CLI argument, a name): refused before anything is simulated."""

    exit_code = 2


def format_key_path(loc: Iterable[str | int]) -> str:
    """``("obstacles", 3, "box", "size")`` -> ``"obstacles[3].box.size"``."""
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += f".{part}" if out else str(part)
    return out or "<top level>"


class SpecError(InputError):
    """A YAML file failed validation; names the file, the key path, the line and the fix.

    Attributes:
        file: the file as given (``None`` for specs built in code).
        key_path: dotted path with indices, e.g. ``obstacles[3].box.size``.
        line: 1-based line in ``file`` (``None`` when unknown).
        problem: what is wrong and what was expected.
    """

    def __init__(
        self,
        problem: str,
        *,
        file: str | Path | None = None,
        key_path: str = "",
        line: int | None = None,
    ) -> None:
        self.file = str(file) if file is not None else None
        self.key_path = key_path
        self.line = line
        self.problem = problem
        super().__init__(self._render())

    def _render(self) -> str:
        where = self.file or "<spec>"
        if self.line is not None:
            where += f":{self.line}"
        key = f" {self.key_path}:" if self.key_path else ""
        return f"{where}:{key} {self.problem}"


class SpecErrors(InputError):
    """Several :class:`SpecError` from one file, reported together."""

    def __init__(self, errors: list[SpecError]) -> None:
        self.errors = errors
        super().__init__("\n".join(str(e) for e in errors))


class UnknownNameError(InputError):
    """A name (planner, generator, executor...) that is not registered; suggests the closest."""

    def __init__(self, kind: str, name: str, known: Iterable[str]) -> None:
        known = sorted(known)
        self.kind, self.name, self.known = kind, name, known
        close = difflib.get_close_matches(name, known, n=1)
        hint = f" Did you mean {close[0]!r}?" if close else ""
        listing = ", ".join(known) if known else "(none registered)"
        super().__init__(f"unknown {kind} {name!r}.{hint} Known: {listing}")


class RobotModelError(InputError):
    """A URDF that lacks the wheel joints or sonar frames nav-bench looks for."""


class PlannerError(NavBenchError):
    """A planner raised or returned something that is not a valid command."""


class SimulationError(NavBenchError):
    """The physics simulation failed (PyBullet error, bad scene)."""
