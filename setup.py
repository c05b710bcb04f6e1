"""Build step: the wheel carries the top-level worlds/, robots/ and configs/ as package data.

The folders at the top of the repository stay the source of truth; building copies them to
``nav_bench/data/`` inside the wheel, where :func:`nav_bench.paths.data_root` finds them through
importlib.resources. An editable install needs no copy: it reads the folders in place.
Everything else is in pyproject.toml.
"""

import shutil
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

DATA_FOLDERS = ("worlds", "robots", "configs")  # the same as nav_bench.paths.DATA_FOLDERS


class BuildPyWithData(build_py):
    def run(self) -> None:
        super().run()
        if getattr(self, "editable_mode", False):
            return
        here = Path(__file__).resolve().parent
        for folder in DATA_FOLDERS:
            source = here / folder
            if not source.is_dir():
                raise SystemExit(f"setup.py: {source} is missing; the wheel needs it")
            target = Path(self.build_lib) / "nav_bench" / "data" / folder
            shutil.copytree(source, target, dirs_exist_ok=True,
                            ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))


setup(cmdclass={"build_py": BuildPyWithData})
