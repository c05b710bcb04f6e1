"""The mapping tests' fixtures: ``grid_kernel`` runs a test module once per
:class:`~nav_bench.mapping.OccupancyGrid` kernel (the NumPy reference and, when Numba is
installed, the compiled one) by changing the constructor's default."""

from __future__ import annotations

import pytest

from nav_bench.mapping import OccupancyGrid
from nav_bench.mapping.occupancy import _kernels

needs_numba = pytest.mark.skipif(_kernels() is None, reason="numba is not installed (the 'fast' extra)")


@pytest.fixture(params=["numpy", pytest.param("numba", marks=needs_numba)])
def grid_kernel(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> str:
    """Every OccupancyGrid built without ``kernel=`` uses this kernel."""
    monkeypatch.setitem(OccupancyGrid.__init__.__kwdefaults__, "kernel", request.param)
    return request.param
