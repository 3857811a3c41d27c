"""STEP import (issue 26): solids read through the optional OpenCASCADE binding (cascadio),
units from the file, each solid a named part; without the binding, one line naming the extra.

tests/data/step/fixture-in.step was written by Open CASCADE's STEP writer (make_fixture.py
beside it): BLOCK 4 x 3 x 1 in and PEG, a cylinder r 1 in, 2.5 in high, 6 in along X, in a
file whose length unit is the inch."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from app_helpers import sync

from valterm.cli import main as cli
from valterm.core.cad.convert import import_cad, native_units
from valterm.core.cad.errors import CadImportError
from valterm.core.cad.step import step_mm_per_unit
from valterm.core.files.setup import read_setup

FIXTURE = Path(__file__).parent / "data" / "step" / "fixture-in.step"
BLOCK_MM = (101.6, 76.2, 25.4)
PEG_MM = (50.8, 50.8, 63.5)


def size(poly) -> np.ndarray:  # type: ignore[no-untyped-def]
    lo, hi = poly.extreme_box
    return hi - lo


def test_two_named_solids_import_with_their_sizes_in_the_files_units() -> None:
    pytest.importorskip("cascadio")
    cell = import_cad(FIXTURE, place_at=(0, 0, 0))
    parts = {p.name: p for p in cell.objects}
    assert sorted(parts) == ["BLOCK", "PEG"]
    assert np.allclose(size(parts["BLOCK"]), BLOCK_MM, atol=0.01)
    # the peg's round side is tessellated: its envelope is at most a sagitta inside the cylinder
    assert np.allclose(size(parts["PEG"]), PEG_MM, atol=0.1)
    # the arrangement is kept: the peg's axis stands 6 in from the block's corner
    offset = parts["PEG"].vertices.mean(axis=0)[:2] - parts["BLOCK"].vertices.min(axis=0)[:2]
    assert np.allclose(offset, (152.4, 38.1), atol=0.5)
    assert cell.units == "IN"  # the setup file keeps the file's inches


def test_units_given_say_what_the_files_numbers_are() -> None:
    pytest.importorskip("cascadio")
    # the numbers 4 x 3 x 1 taken as millimetres: 25.4 times smaller, with the unit warning
    cell = import_cad(FIXTURE, units="MM", place_at=(0, 0, 0))
    block = next(p for p in cell.objects if p.name == "BLOCK")
    assert np.allclose(size(block), np.array(BLOCK_MM) / 25.4, atol=0.001)
    assert cell.units == "MM"


def test_valterm_import_writes_the_named_parts(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("cascadio")
    assert cli(["--workspace", str(tmp_path), "import", str(FIXTURE), "--out", "FIXTURE.SET"]) == 0
    out = capsys.readouterr().out
    assert "part 1 " in out and "BLOCK" in out and "PEG" in out
    text = (tmp_path / "FIXTURE.SET").read_text()
    assert "; NAME BLOCK" in text and "; NAME PEG" in text
    cell = read_setup(tmp_path / "FIXTURE.SET")  # read back: names and sizes survive the file
    parts = {p.name: p for p in cell.objects}
    assert cell.units == "IN" and sorted(parts) == ["BLOCK", "PEG"]
    assert np.allclose(size(parts["BLOCK"]), BLOCK_MM, atol=0.01)


def test_the_file_says_its_units() -> None:
    assert step_mm_per_unit(FIXTURE) == 25.4 and native_units(FIXTURE) == "IN"
    si = b"#1 = ( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );\n"
    assert step_mm_per_unit("x.step", b"ISO-10303-21;\n" + si) == 1.0
    assert step_mm_per_unit("x.step", si.replace(b".MILLI.", b"$")) == 1000.0
    assert step_mm_per_unit("x.step", b"ISO-10303-21;\nENDSEC;\n") == 1.0  # none said: millimetres


def test_without_the_extra_one_line_names_it(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setitem(sys.modules, "cascadio", None)  # `import cascadio` now raises ImportError
    assert cli(["--workspace", str(tmp_path), "import", str(FIXTURE), "--out", "FIXTURE.SET"]) == 1
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "pip install 'valterm[step]'" in lines[0] and "cascadio" in lines[0], err
    assert "Traceback" not in err and not (tmp_path / "FIXTURE.SET").exists()
    with pytest.raises(CadImportError, match=r"valterm\[step\]"):
        import_cad(FIXTURE)


def test_a_file_that_is_not_step_is_refused_before_the_binding_is_asked(tmp_path: Path) -> None:
    path = tmp_path / "junk.stp"
    path.write_text("solid not a step file\n")
    with pytest.raises(CadImportError, match=r"junk.stp:1: not a STEP file"):
        import_cad(path)


@sync
async def test_the_start_screens_cad_prompt_reads_a_step_file(tmp_path: Path) -> None:
    pytest.importorskip("cascadio")
    from app_helpers import make_app, screen_text, until

    from valterm.core.workspace import Workspace

    Workspace.open(tmp_path)
    (tmp_path / "PARTS.STP").write_bytes(FIXTURE.read_bytes())
    app = make_app(tmp_path, start=True)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.press("U", *"PARTS.STP", "enter", *"PARTS", "enter", "2", "enter")
        await pilot.pause()
        assert "THE FILE SAYS IN" in screen_text(app)  # the units question offers the file's inches
        await pilot.press("enter", "enter")
        await until(pilot, lambda: "PARTS.SET HAS SUCCESSFULLY BEEN WRITTEN" in screen_text(app), "PARTS.SET written")
        assert "PARTS.SET HAS SUCCESSFULLY BEEN WRITTEN" in screen_text(app)
    cell = read_setup(tmp_path / "PARTS.SET")
    assert cell.units == "IN" and sorted(p.name for p in cell.objects) == ["BLOCK", "PEG"]
