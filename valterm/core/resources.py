"""The one place that finds bundled data: everything under ``valterm/data`` in the package.

The data lives at the repository's top level, where users and contributors look for it:
``assets/`` (the robot files, COMMAND.DAT, HELPER.DAT, DEMO.KEYS, the served page),
``cells/`` and ``programs/``. ``valterm/data``'s entries are links to them: an editable
checkout reads through the links, and the build copies what they point at into the sdist
and the wheel (``[tool.setuptools.package-data]``), so an installed wheel finds the same
files wherever it is run from. Nothing here is read at import time.
"""

from __future__ import annotations

import tomllib
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from importlib.resources.abc import Traversable

PACKAGE = "valterm"
DATA = "data"
# The package's folder: what ``importlib.resources.files(PACKAGE)`` gives for a package on
# disk (a wheel unpacked, a checkout), without importlib.resources' readers and zipfile
# (about 8 ms of every start, issue 25).
PACKAGE_DIR = Path(__file__).parent.parent

# The bundled folders a new workspace is filled from (SPEC §5.1).
CELLS = "cells"
PROGRAMS = "programs"


def data_root() -> Traversable:
    """The package's data folder."""
    return PACKAGE_DIR / DATA


def data_path(*parts: str) -> Path:
    """A bundled file or folder as a file-system path.

    pip, pipx and uv unpack wheels onto disk, so the resource is a real path; a zipped
    import (which none of them makes) would fail here loudly rather than half-work.
    """
    found = data_root().joinpath(*parts)
    return Path(str(found))


def read_text(*parts: str) -> str:
    """The text of a bundled file (UTF-8)."""
    return data_root().joinpath(*parts).read_text(encoding="utf-8")


@lru_cache(maxsize=8)
def read_toml(*parts: str) -> dict[str, Any]:
    """The tables of a bundled TOML file, parsed once a process: a session's start reads the
    robot file for its geometry, its drawn model and its timing (three parses of one file,
    issue 25). The tables are shared by every caller: read them, never change them."""
    return tomllib.loads(read_text(*parts))


def bundled_files(folder: str) -> list[Path]:
    """The files of a bundled folder (``cells`` or ``programs``), sorted by name."""
    root = data_path(folder)
    return sorted(p for p in root.iterdir() if p.is_file())
