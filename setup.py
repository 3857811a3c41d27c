"""The build's one step past pyproject.toml: the data at the top level (assets/, cells/,
programs/) is copied into the package as valterm/data/ (valterm/core/resources.py reads it
there in an installed wheel, and at the top level in a checkout). No links: a checkout is the
same on every system."""

from pathlib import Path
from shutil import copytree

from setuptools import setup
from setuptools.command.build_py import build_py

DATA_FOLDERS = ("assets", "cells", "programs")  # as valterm/core/resources.py names them


class BuildWithData(build_py):
    def run(self) -> None:
        super().run()
        if self.editable_mode:  # an editable install reads the checkout's top level
            return
        data = Path(self.build_lib) / "valterm" / "data"
        for folder in DATA_FOLDERS:
            copytree(folder, data / folder, dirs_exist_ok=True,
                     ignore=lambda _dir, names: [n for n in names if n == "__pycache__"])


setup(cmdclass={"build_py": BuildWithData})
