"""The simulator core imports neither textual nor rich (each module in a fresh interpreter)."""

from __future__ import annotations

import importlib.util
import subprocess
import sys

import pytest

CORE_MODULES = [
    "valterm.kinematics", "valterm.motion", "valterm.robot", "valterm.simulator",
    "valterm.session", "valterm.events", "valterm.bench", "valterm.cli",
    "valterm.cell.polyhedron", "valterm.cell.workcell",
    "valterm.files.setup", "valterm.files.locations", "valterm.files.programs",
    "valterm.files.datfiler", "valterm.files.variables", "valterm.workspace",
    "valterm.cad.iges", "valterm.cad.mesh", "valterm.cad.convert", "valterm.cad.export",
    "valterm.collision.thesis", "valterm.collision.exact", "valterm.collision.grasp",
    "valterm.collision.world",
    "valterm.val.interpreter", "valterm.val.checker", "valterm.val.commands",
    "valterm.editor",
    "valterm.ui.view.raster", "valterm.ui.view.clock",
]


@pytest.mark.parametrize("module", CORE_MODULES)
def test_core_module_loads_no_ui_library(module: str) -> None:
    if importlib.util.find_spec(module) is None:
        pytest.fail(f"{module} is listed as core but does not exist")
    code = (
        f"import sys, {module}\n"
        "bad = [m for m in ('textual', 'rich') if m in sys.modules]\n"
        "assert not bad, bad\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
