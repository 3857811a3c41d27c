"""The start screen's IGES import (I) driven with Pilot: it asks before replacing a setup file,
can add the parts to it, and offers the file's own units from the IGES header."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from app_helpers import make_app, screen_text, sync
from iges_writer import Sample, of_kind

from valterm.core.files.setup import read_setup
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.screens.start import StartScreen

def workspace_with(tmp_path: Path, source: Path, name: str) -> Path:
    """A seeded workspace holding the IGES sample as NAME.IGS."""
    from valterm.core.workspace import Workspace
    Workspace.open(tmp_path)
    shutil.copyfile(source, tmp_path / f"{name}.IGS")
    return tmp_path


async def answer_up_to_replace(pilot, cad: str, setup: str) -> None:  # type: ignore[no-untyped-def]
    await pilot.press("I", *cad, "enter", *setup, "enter")
    await pilot.pause()


async def answer_the_rest(pilot) -> None:  # type: ignore[no-untyped-def]
    """One workpiece; RETURN accepts the offered units and W."""
    await pilot.press("1", "enter", "enter", "enter")
    await pilot.pause()


@pytest.mark.parametrize("keys", [["N"], ["escape"]])
@of_kind("box")
@sync
async def test_no_or_escape_keeps_the_existing_setup_byte_for_byte(tmp_path: Path, keys: list[str],
                                                                    sample: Sample) -> None:
    workspace_with(tmp_path, sample.path, "BOX")
    before = (tmp_path / "PROCESS.SET").read_bytes()
    app = make_app(tmp_path, start=True)
    async with app.run_test(size=(160, 50)) as pilot:
        await answer_up_to_replace(pilot, "BOX", "PROCESS")
        assert "PROCESS.SET EXISTS" in screen_text(app)
        await pilot.press(*keys)
        await pilot.pause()
        assert "PART TRANSFER ENDED" in screen_text(app)
        assert isinstance(app.screen, StartScreen)
        await pilot.press(*"1", "enter")   # nothing more is asked: keys go back to the menu
        await pilot.pause()
    assert (tmp_path / "PROCESS.SET").read_bytes() == before


@of_kind("box")
@sync
async def test_yes_replaces_the_existing_setup(tmp_path: Path, sample: Sample) -> None:
    workspace_with(tmp_path, sample.path, "BOX")
    app = make_app(tmp_path, start=True)
    async with app.run_test(size=(160, 50)) as pilot:
        await answer_up_to_replace(pilot, "BOX", "PROCESS")
        await pilot.press("Y")
        await answer_the_rest(pilot)
        assert isinstance(app.screen, MainMenuScreen)
        assert "SETUP FILE PROCESS.SET WITH 1 PARTS" in screen_text(app)
    cell = read_setup(tmp_path / "PROCESS.SET")
    assert [p.name for p in cell.objects] == ["BOX"]
    assert np.allclose(np.ptp(cell.objects[0].vertices, axis=0), sample.size_mm)
    assert cell.objects[0].vertices[:, 0].min() > 102   # on the table in front, not in the robot


@of_kind("box")
@sync
async def test_a_adds_the_parts_to_the_existing_setup(tmp_path: Path, sample: Sample) -> None:
    workspace_with(tmp_path, sample.path, "BOX")
    before = read_setup(tmp_path / "PROCESS.SET")
    app = make_app(tmp_path, start=True)
    async with app.run_test(size=(80, 24)) as pilot:
        await answer_up_to_replace(pilot, "BOX", "PROCESS")
        await pilot.press("A")
        await answer_the_rest(pilot)
        assert isinstance(app.screen, MainMenuScreen)
        assert f"SETUP FILE PROCESS.SET WITH {len(before.objects) + 1} PARTS" in screen_text(app)
        assert len(app.session.simulator.cell.objects) == len(before.objects) + 1
    after = read_setup(tmp_path / "PROCESS.SET")
    assert len(after.objects) == len(before.objects) + 1
    for a, b in zip(before.objects, after.objects):
        np.testing.assert_allclose(a.vertices, b.vertices, atol=0.005)
    assert after.objects[-1].name == "BOX"  # named after the file (no entity label)


@of_kind("wireframe")
@sync
async def test_units_question_offers_the_iges_header_units(tmp_path: Path, sample: Sample) -> None:
    workspace_with(tmp_path, sample.path, "CHASSIS")
    app = make_app(tmp_path, start=True)
    async with app.run_test(size=(160, 50)) as pilot:
        await answer_up_to_replace(pilot, "CHASSIS", "CHASSIS")   # a new setup: no question
        await pilot.press("1", "enter")
        await pilot.pause()
        assert "THE FILE SAYS IN" in screen_text(app)
        await pilot.press("enter", "enter")   # accept the offered units, then W
        await pilot.pause()
        # about 2 m long: no table holds it; the warning waits to be read
        assert "NO FREE SPOT ON A TABLE" in screen_text(app)
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, MainMenuScreen)
    cell = read_setup(tmp_path / "CHASSIS.SET")
    assert cell.units == "IN"
    # read in inches, kept in mm: the CAD chassis is 73.5 in long, 1867 mm, not 73.5 mm
    assert np.ptp(cell.objects[0].vertices, axis=0)[0] == pytest.approx(sample.size_mm[0], abs=0.01)
    text = (tmp_path / "CHASSIS.SET").read_text()
    assert "e-" not in text and all(len(f.split(".")[-1]) == 4 for f in text.split()[4:] if "." in f and f[0] != ";")
