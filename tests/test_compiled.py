"""nav_bench.compiled: a kernel module is None without Numba, and other import errors surface."""

import sys

import pytest

from nav_bench import compiled


@pytest.fixture(autouse=True)
def _fresh_cache():
    compiled.load.cache_clear()
    compiled.numba_version.cache_clear()
    yield
    compiled.load.cache_clear()
    compiled.numba_version.cache_clear()


def test_a_kernel_module_is_none_when_numba_cannot_be_imported(monkeypatch, tmp_path):
    (tmp_path / "needs_numba_mod.py").write_text("import numba\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(sys.modules, "numba", None)  # import numba -> ImportError
    assert compiled.load("needs_numba_mod") is None


def test_the_numba_version_is_none_without_numba_and_numbas_own_with_it(monkeypatch):
    # run.json records it: the kernels change a run's CPU times, not its rows
    numba = pytest.importorskip("numba")
    assert compiled.numba_version() == numba.__version__
    compiled.numba_version.cache_clear()
    monkeypatch.setitem(sys.modules, "numba", None)
    assert compiled.numba_version() is None


def test_a_numba_that_refuses_this_numpy_counts_as_no_numba(monkeypatch, tmp_path):
    # Numba raises "Numba needs NumPy 2.3 or less" as a plain ImportError (no module name)
    (tmp_path / "numba.py").write_text("raise ImportError('Numba needs NumPy 2.3 or less. Got NumPy 2.9.')\n")
    (tmp_path / "kernel_mod_x.py").write_text("import numba\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "numba", raising=False)
    assert compiled.load("kernel_mod_x") is None


def test_an_import_error_of_anything_but_numba_is_raised(tmp_path, monkeypatch):
    (tmp_path / "broken_kernel_mod.py").write_text("import no_such_module_anywhere\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(ImportError, match="no_such_module_anywhere"):
        compiled.load("broken_kernel_mod")


def test_a_kernel_compiles_and_computes_what_python_computes():
    pytest.importorskip("numba")

    def axpy(a, x, y):
        return a * x + y

    fast = compiled.kernel()(axpy)
    assert fast(3.0, 0.1, 0.2) == axpy(3.0, 0.1, 0.2)
