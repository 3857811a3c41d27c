"""The data at the top level (issues 26 and 37): assets/, cells/ and programs/ hold the files;
the build copies them into the wheel as valterm/data/ (setup.py, no links); the one resources
module finds them in either layout."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from valterm.core import resources

ROOT = Path(__file__).resolve().parent.parent
# what callers name (as the package holds it) -> where the repository keeps it
NAMES = {("cells", "PROCESS.SET"): "cells/PROCESS.SET", ("programs", "PROCESS.DAT"): "programs/PROCESS.DAT",
         ("robot", "PUMA.toml"): "assets/robot/PUMA.toml", ("COMMAND.DAT",): "assets/COMMAND.DAT",
         ("HELPER.DAT",): "assets/HELPER.DAT", ("DEMO.KEYS",): "assets/DEMO.KEYS", ("web",): "assets/web"}


def test_the_top_level_holds_the_data_and_no_links() -> None:
    for wanted in NAMES.values():
        assert (ROOT / wanted).exists() and not (ROOT / wanted).is_symlink(), wanted
    links = [str(p.relative_to(ROOT)) for folder in ("valterm", "assets", "cells", "programs")
             for p in (ROOT / folder).rglob("*") if p.is_symlink()]
    assert links == []


def test_resources_find_each_name_where_the_layout_keeps_it() -> None:
    installed = Path(resources.PACKAGE_DIR) / resources.DATA
    top = installed if installed.is_dir() else ROOT  # a wheel's data, else the checkout's
    for parts, wanted in NAMES.items():
        assert resources.data_path(*parts).resolve() == (top / wanted).resolve()
    assert resources.read_text("COMMAND.DAT") == (ROOT / "assets/COMMAND.DAT").read_text(encoding="utf-8")
    assert {p.name for p in resources.bundled_files(resources.CELLS)} == {
        p.name for p in (ROOT / "cells").iterdir() if p.is_file()}


def test_the_built_wheel_carries_the_data_inside_the_package(tmp_path: Path) -> None:
    """setup.py's build step: every file of the three folders, under valterm/data/."""
    if not (ROOT / "setup.py").is_file():
        pytest.skip("not a source tree")
    shutil.copytree(ROOT, tmp_path / "src", ignore=shutil.ignore_patterns(
        ".venv", ".git", "build", "dist", "*.egg-info", "__pycache__", ".hypothesis", ".pytest_cache", "tests"))
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    result = subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps",
                             "-w", str(tmp_path / "dist"), str(tmp_path / "src")],
                            capture_output=True, text=True, env=env, timeout=300)
    assert result.returncode == 0, result.stderr[-2000:]
    (wheel,) = (tmp_path / "dist").glob("*.whl")
    with zipfile.ZipFile(wheel) as whl:
        inside = {n for n in whl.namelist() if n.startswith("valterm/data/")}
    wanted = {f"valterm/data/{p.relative_to(ROOT)}" for folder in resources.DATA_FOLDERS
              for p in (ROOT / folder).rglob("*") if p.is_file() and "__pycache__" not in p.parts}
    assert len(wanted) > 30 and wanted == inside
