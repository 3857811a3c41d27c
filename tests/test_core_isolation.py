"""The simulator core imports neither textual nor rich: every module under valterm/core (found,
not listed by hand), and the command line's entry points, in a fresh interpreter."""

from __future__ import annotations

import pkgutil
import subprocess
import sys

import valterm.core

# Not core, but they must start without the UI libraries too (the app imports them itself).
ENTRY_POINTS = ["valterm.cli", "valterm.bench.suite"]


def core_modules() -> list[str]:
    found = pkgutil.walk_packages(valterm.core.__path__, prefix="valterm.core.")
    return sorted(module.name for module in found)


def test_the_core_is_found_whole() -> None:
    modules = core_modules()
    for expected in ("valterm.core.kinematics", "valterm.core.val.interpreter", "valterm.core.render.raster",
                     "valterm.core.files.demokeys", "valterm.core.text.transcript"):
        assert expected in modules
    assert len(modules) > 50


def test_no_core_module_loads_a_ui_library() -> None:
    """Each module imported in turn; the first that brings textual or rich in is named."""
    code = (
        "import importlib, sys\n"
        "for name in sys.argv[1:]:\n"
        "    importlib.import_module(name)\n"
        "    bad = [m for m in ('textual', 'rich') if m in sys.modules]\n"
        "    assert not bad, f'{name} loads {bad}'\n"
    )
    modules = core_modules() + ENTRY_POINTS
    result = subprocess.run([sys.executable, "-c", code, *modules], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr[-2000:]
