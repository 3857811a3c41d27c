"""The data at the top level (issue 26): assets/, cells/ and programs/ hold the files, the
package's valterm/data holds links to them, and the one resources module reads through them."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.core import resources

ROOT = Path(__file__).resolve().parent.parent
LINKS = {"cells": "cells", "programs": "programs", "robot": "assets/robot", "web": "assets/web",
         "COMMAND.DAT": "assets/COMMAND.DAT", "HELPER.DAT": "assets/HELPER.DAT", "DEMO.KEYS": "assets/DEMO.KEYS"}


def test_the_top_level_holds_the_data() -> None:
    for folder, wanted in (("assets", "robot/PUMA.toml"), ("cells", "PROCESS.SET"), ("programs", "PROCESS.DAT")):
        path = ROOT / folder / wanted
        assert path.is_file() and not path.is_symlink(), path


def test_the_package_data_are_links_to_the_top_level() -> None:
    data = ROOT / "valterm" / "data"
    if not data.is_dir() or not (data / "cells").is_symlink():
        pytest.fail("valterm/data's entries must be links to the top level (a checkout without symlinks?)")
    assert sorted(p.name for p in data.iterdir()) == sorted(LINKS)
    for name, target in LINKS.items():
        link = data / name
        assert link.is_symlink(), link
        assert link.resolve() == (ROOT / target).resolve(), (link, link.resolve())


def test_resources_read_the_top_level_files_through_the_links() -> None:
    assert resources.data_path("robot", "PUMA.toml").resolve() == (ROOT / "assets/robot/PUMA.toml").resolve()
    assert resources.read_text("COMMAND.DAT") == (ROOT / "assets/COMMAND.DAT").read_text(encoding="utf-8")
    assert {p.name for p in resources.bundled_files(resources.CELLS)} == {
        p.name for p in (ROOT / "cells").iterdir() if p.is_file()}


def test_the_data_folder_is_the_one_importlib_resources_finds() -> None:
    """resources finds the package's folder itself (issue 25: importlib.resources' readers and
    zipfile are not loaded at the start); for a package on disk it is the same folder."""
    from importlib.resources import files

    assert resources.data_root() == files(resources.PACKAGE) / resources.DATA
    assert Path(str(resources.data_root())).is_dir()
