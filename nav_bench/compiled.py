"""Numba for the hot loops, when it is installed (the optional ``fast`` extra).

Every compiled kernel in nav-bench is an exact twin of a NumPy or Python reference that runs
when Numba is missing: the same IEEE operations in the same order, so results are the same bit
for bit either way (no fast-math; no ``exp``, ``arctan2`` or ``pow`` inside a kernel, whose last
bits differ between NumPy's SIMD loops and the C library Numba calls; ``hypot``, ``sqrt``,
``sin`` and ``cos`` agree). The kernel modules import Numba at import time; callers reach them
through :func:`load`, which says None when Numba cannot be imported.

Compiled functions are cached on disk (``cache=True``): in ``__pycache__`` beside their module,
else in the user's cache folder (``~/.cache/numba``) or ``NUMBA_CACHE_DIR``; where none is
writable they are compiled in each process instead (:func:`kernel`).
"""

from __future__ import annotations

import functools
import importlib
from collections.abc import Callable
from types import ModuleType
from typing import Any

from nav_bench.errors import InputError


def kernel_choices(reference: str = "numpy") -> tuple[str, str, str]:
    """The choices of a kernel setting: ``auto`` (compiled when Numba loads), ``reference`` (the
    uncompiled code: "numpy", or "python" for D* Lite's search) and ``numba``."""
    return ("auto", reference, "numba")


def kernel(**options: Any) -> Callable[[Callable[..., Any]], Any]:
    """``numba.njit(**options)`` with an on-disk cache, or without one where Numba finds no
    writable cache folder (it raises at decoration then: a read-only install with no writable
    home). Only kernel modules call this: it imports Numba."""
    from numba import njit

    def compile_(fn: Callable[..., Any]) -> Any:
        try:
            return njit(cache=True, **options)(fn)
        except RuntimeError:  # "cannot cache function ...: no locator available"
            return njit(cache=False, **options)(fn)

    return compile_


@functools.cache
def numba_version() -> str | None:
    """The version of the Numba the kernels run on, or None when it cannot be imported (the
    kernels' NumPy/Python references run then; :func:`load`'s rule)."""
    try:
        return str(importlib.import_module("numba").__version__)
    except ImportError:
        return None


@functools.cache
def load(module: str) -> ModuleType | None:
    """The kernel module ``module`` (dotted name), or None when Numba cannot be imported: the
    ``fast`` extra is not installed, or this Numba refuses this NumPy (it raises an ImportError
    of its own then, naming no module). Imported on first use only (Numba's import takes
    ~0.3 s), and remembered. An error in the kernel module itself is raised."""
    if numba_version() is None:
        return None
    return importlib.import_module(module)


def use_kernels(choice: str, kernels: Callable[[], ModuleType | None], what: str,
                reference: str = "numpy") -> bool:
    """Whether an object offering the choice ``choice`` (:func:`kernel_choices`, with
    ``reference`` naming its uncompiled code: "numpy", or "python" for D* Lite's search) runs
    compiled kernels: the reference never, ``numba`` always (an :class:`~nav_bench.errors.InputError` naming
    the ``fast`` extra without Numba), ``auto`` when they load. ``kernels``: the caller's loader
    of its kernel module (a :func:`load`; None without Numba). ``what`` names the object in the
    errors ("occupancy grid", "carving", "search")."""
    choices = kernel_choices(reference)
    if choice not in choices:
        raise InputError(f"{what} kernel must be one of {list(choices)}, got {choice!r}")
    if choice == reference:
        return False
    if kernels() is None:
        if choice == "numba":
            raise InputError(f"{what} kernel 'numba' needs Numba: pip install 'nav-bench[fast]'")
        return False
    return True
