"""The simulator core imports neither textual nor rich (each module in a fresh interpreter)."""

from __future__ import annotations

import importlib.util
import subprocess
import sys

import pytest

CORE_MODULES = [
    "valterm.core.kinematics", "valterm.core.motion", "valterm.core.robot", "valterm.core.simulator",
    "valterm.core.session", "valterm.core.events", "valterm.bench.suite", "valterm.cli",
    "valterm.core.cell.polyhedron", "valterm.core.cell.workcell",
    "valterm.core.files.setup", "valterm.core.files.locations", "valterm.core.files.programs",
    "valterm.core.files.datfiler", "valterm.core.files.variables", "valterm.core.workspace",
    "valterm.core.cad.iges", "valterm.core.cad.mesh", "valterm.core.cad.convert", "valterm.core.cad.export",
    "valterm.core.collision.thesis", "valterm.core.collision.exact", "valterm.core.collision.grasp",
    "valterm.core.collision.world",
    "valterm.core.val.interpreter", "valterm.core.val.checker", "valterm.core.val.commands",
    "valterm.core.editor", "valterm.core.files.demokeys",
    "valterm.core.render.raster", "valterm.core.render.clock",
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
