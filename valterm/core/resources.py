"""The one place that finds bundled data.

The data lives at the repository's top level, where users and contributors look for it:
``assets/`` (the robot files, COMMAND.DAT, HELPER.DAT, DEMO.KEYS, the served page),
``cells/`` and ``programs/``. The build copies those three folders into the package as
``valterm/data/`` (``setup.py``: a build-time mapping, no links), so an installed wheel finds
them inside itself wherever it is run from; a checkout (an editable install) has no
``valterm/data`` and reads the top level itself. Callers name a file as the package holds
it (``robot/PUMA.toml``, ``COMMAND.DAT``, ``cells/PROCESS.SET``); which folder of the two
layouts holds it is decided here alone. Nothing here is read at import time.
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
# the top-level folders that hold the data, in the repository and in the package's data
DATA_FOLDERS = ("assets", "cells", "programs")
# The package's folder: what ``importlib.resources.files(PACKAGE)`` gives for a package on
# disk (a wheel unpacked, a checkout), without importlib.resources' readers and zipfile
# (about 8 ms of every start, issue 25).
PACKAGE_DIR = Path(__file__).parent.parent

# The bundled folders a new workspace is filled from (SPEC §5.1).
CELLS = "cells"
PROGRAMS = "programs"


def data_root() -> Traversable:
    """The folder holding ``assets``, ``cells`` and ``programs``: the package's data folder
    when installed from a wheel, else the checkout's top level."""
    installed = PACKAGE_DIR / DATA
    return installed if installed.is_dir() else PACKAGE_DIR.parent


def _place(parts: tuple[str, ...]) -> tuple[str, ...]:
    """Where a bundled name lives under the data root: cells and programs have folders of
    their own, everything else is an asset."""
    if parts and parts[0] in (CELLS, PROGRAMS):
        return parts
    return ("assets", *parts)


def data_path(*parts: str) -> Path:
    """A bundled file or folder as a file-system path.

    pip, pipx and uv unpack wheels onto disk, so the resource is a real path; a zipped
    import (which none of them makes) would fail here loudly rather than half-work.
    """
    found = data_root().joinpath(*_place(parts))
    return Path(str(found))


def read_text(*parts: str) -> str:
    """The text of a bundled file (UTF-8)."""
    return data_root().joinpath(*_place(parts)).read_text(encoding="utf-8")


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
