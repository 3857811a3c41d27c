"""Issue 25 (start time): what the app loads before MAIN MENU. The heavy readers and checkers
load when first used; each is still there when asked for."""

from __future__ import annotations

import json
import subprocess
import sys

HEAVY = ("trimesh", "fcl", "valterm.core.cad.iges", "valterm.core.cad.iges_entities",
         "valterm.core.val.interpreter", "valterm.core.val.debugger", "valterm.core.val.vplus")


def _loaded(code: str) -> list[str]:
    probe = f"{code}\nimport json, sys\nprint(json.dumps(sorted(m for m in {HEAVY!r} if m in sys.modules)))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    loaded: list[str] = json.loads(out.stdout.strip().splitlines()[-1])
    return loaded


def test_the_app_and_its_session_start_without_the_heavy_modules() -> None:
    code = ("import valterm.cli, valterm.ui.app\n"
            "from valterm.core.session import Session\n"
            "import tempfile\n"
            "s = Session(tempfile.mkdtemp())\n"
            "s.simulator.robot_polyhedra()")
    assert _loaded(code) == []


def test_each_loads_when_first_used() -> None:
    code = ("import tempfile\n"
            "import valterm.core.cad as cad\n"
            "from valterm.core.session import Session\n"
            "cad.read_iges\n"
            "Session(tempfile.mkdtemp()).interpreter")
    assert {"valterm.core.cad.iges", "valterm.core.val.interpreter"} <= set(_loaded(code))
