"""The museum demo: the key script (core), the demo app played with Pilot (captions shown, the
model moving, a visitor taking over, kiosk mode surviving random keys and resuming after the
idle time) and ``valterm demo``'s exit status."""

from __future__ import annotations

import asyncio
import functools
import math
import random
import re
from pathlib import Path

import pytest

from app_helpers import WAIT_LIMIT, until
from valterm.core.errors import ValtermError
from valterm.core.files.demokeys import DemoScriptError, load_demo, parse_demo
from valterm.ui.demo import DEMO_HINT, Caption, DemoApp, Stage

ITEMS = load_demo()
FAST = 1000.0  # the demo's speed factor in tests: pauses and gaps all but vanish

SHORT = """@ Read the setup file PROCESS.
E
RETURN
@ Keyboard menu, axes on.
K
A
R
"""
HELD = SHORT + "PAUSE 300\n"  # the short script, then a long pause (30 s at speed 10)



# -- the key script -----------------------------------------------------------------------
def test_script_errors_are_located_core_errors() -> None:
    with pytest.raises(DemoScriptError) as caught:
        parse_demo('@ hello\nE\n"DEMO3.SET\n', "MY.KEYS")
    assert isinstance(caught.value, ValtermError)
    assert str(caught.value) == "MY.KEYS:3: a typed text ends with a quote"
    with pytest.raises(DemoScriptError, match="DEMO.KEYS:2: PAUSE takes seconds"):
        parse_demo("E\nPAUSE soon\n")
    with pytest.raises(DemoScriptError, match="presses no key"):
        parse_demo("@ only words\n")
    with pytest.raises(DemoScriptError, match="NOPE.KEYS: no such key script file"):
        load_demo("/nonexistent/NOPE.KEYS")


def test_every_phase_has_a_caption_that_fits_two_lines() -> None:
    assert ITEMS[0].kind == "caption" and DEMO_HINT in ITEMS[0].value
    captions = [item.value for item in ITEMS if item.kind == "caption"]
    assert len(captions) >= 25
    # two lines of an 80-column terminal, the hint included
    assert all(0 < len(c) + len(DEMO_HINT) + 2 <= 2 * 78 for c in captions), max(captions, key=len)
    keys_since_caption = 0
    for item in ITEMS:
        if item.kind == "caption":
            keys_since_caption = 0
        elif item.kind in ("key", "text") and not item.replay_only:
            keys_since_caption += 1
            assert keys_since_caption <= 20, f"DEMO.KEYS:{item.line}: a phase without a caption"


# -- each caption against what its stage printed ---------------------------------------------
SAYS_STOP = re.compile(r"\b(stops?|stopped|refuses?|refused)\b", re.IGNORECASE)
OUTCOME = re.compile(r"^(PROGRAM \S+ COMPLETED|\*\*\*|MOTION REFUSED)")


def caption_faults(stage: Stage) -> list[str]:
    """Where a caption is not what its stage printed: a claim (``= TEXT``) no line holds, a
    stop or refusal it announces that did not happen or one that happened unannounced, and a
    program's outcome (COMPLETED, an error) no claim of it checks."""
    printed = [line.upper() for line in stage.printed]
    faults = [f"claims {claim!r}, which it never printed" for claim in stage.claims
              if not any(claim in line for line in printed)]
    refused = [line for line in printed if line.startswith(("***", "MOTION REFUSED"))]
    if SAYS_STOP.search(stage.caption) and not refused:
        completed = [line for line in printed if " COMPLETED" in line]
        faults.append(f"announces a stop, but nothing stopped {completed}")
    if refused and not SAYS_STOP.search(stage.caption):
        faults.append(f"says nothing of {refused[0]!r}")
    faults += [f"prints {line!r}, which no claim checks" for line in printed
               if OUTCOME.match(line) and not any(claim in line for claim in stage.claims)]
    return faults


def test_the_caption_check_finds_a_stop_that_never_came() -> None:
    """The CONV1 caption as it was: it announced a stop at joint 4; the run said COMPLETED."""
    old = Stage("CONV1 runs. In CONV2 the wrist would pass its joint 4 stop: the simulator stops there, "
                "as the PUMA would.", (), ("CONV1      55  RETURN", "PROGRAM CONV1 COMPLETED: 1 LOOP"))
    assert [fault.split(",")[0] for fault in caption_faults(old)] == ["announces a stop", "prints 'PROGRAM CONV1 COMPLETED: 1 LOOP'"]
    unsaid = Stage("I makes each turn larger.", ("CLAMP IS NEAR PART 10",),
                   ("CLAMP IS NEAR PART 10", "MOTION REFUSED: JOINT 3 BEYOND ITS STOP (258.00 DEG, STOP -45..225)"))
    assert len(caption_faults(unsaid)) == 2  # the refusal unsaid, and unclaimed
    assert caption_faults(Stage("CONV1 runs to its end.", ("COMPLETED",), ("PROGRAM CONV1 COMPLETED: 1 LOOP",))) == []
    missing = Stage("PROCESS runs once.", ("PROGRAM PROCESS COMPLETED",), ("*** PROCESS STEP 6: OUT OF REACH",))
    assert len(caption_faults(missing)) == 3


def test_claims_are_read_from_the_script() -> None:
    items = parse_demo('@ CONV1 runs.\n= program conv1 completed\n"EXEC CONV1"\n=\n')
    assert [(item.kind, item.value) for item in items] == [
        ("caption", "CONV1 runs."), ("claim", "PROGRAM CONV1 COMPLETED"), ("text", "EXEC CONV1"), ("key", "=")]
    assert sum(item.kind == "claim" for item in ITEMS) >= 10


# -- the demo app ---------------------------------------------------------------------------
def sync(test):  # type: ignore[no-untyped-def]
    @functools.wraps(test)
    def run(*args, **kwargs) -> None:  # type: ignore[no-untyped-def]
        asyncio.run(test(*args, **kwargs))

    return run


def caption_shown(app: DemoApp) -> str:
    return str(app.screen.query_one(Caption).render())


@sync
async def test_demo_plays_the_whole_session_once_with_captions() -> None:
    app = DemoApp(ITEMS, speed=FAST, once=True, motion_rate=math.inf)
    poses: set[tuple[float, ...]] = set()
    shown: set[str] = set()
    program = ""
    async with app.run_test(size=(100, 40)) as pilot:
        await until(pilot, lambda: app.screen.query(Caption), "a caption on the start screen")
        end = asyncio.get_running_loop().time() + WAIT_LIMIT  # a stuck demo fails, never hangs CI
        while app.is_running and app.return_code is None:
            if asyncio.get_running_loop().time() > end:
                pytest.fail(f"the demo never ended: {type(app.screen).__name__} on top, captions "
                            f"{len(app.captions)} of the script's, playing {app.playing}, moving {app.moving}, "
                            f"keys waiting {app.keys_waiting}, rounds {app.rounds}")
            test_dat = Path(str(app.workspace_root)) / "TEST.DAT"
            if test_dat.is_file():
                program = test_dat.read_text()
            if app.session is not None:
                poses.add(tuple(round(j, 3) for j in app.session.simulator.joints))
            found = app.screen.query(Caption)
            if found:
                shown.add(str(found.first().render()))
            await pilot.pause(0.05)
    assert app.return_code == 0
    script = [item.value for item in ITEMS if item.kind == "caption" and not item.replay_only]
    assert list(app.captions) == script
    # the visitor saw the captions on the screens (several phases, read back from the widget)
    # the keys reached the right screens: the editor wrote Table C-2's program
    assert program.split() == ["MOVE", "A", "MOVE", "B", "MOVE", "E", "STOP"]
    assert sum(any(c in s for s in shown) for c in script) >= 10
    assert len(poses) >= 5  # jogging and two programs moved the robot
    # every stage played, and each caption says what its stage printed (issue 35 item 7)
    assert [stage.caption for stage in app.stages] == script
    faults = {stage.caption: caption_faults(stage) for stage in app.stages if caption_faults(stage)}
    assert not faults, faults
    conv1 = next(stage for stage in app.stages if stage.caption.startswith("CONV1 runs"))
    assert "PROGRAM CONV1 COMPLETED: 1 LOOP" in conv1.printed and "stop" not in conv1.caption


@sync
async def test_a_key_hands_over_and_the_idle_time_restarts_the_demo() -> None:
    app = DemoApp(parse_demo(HELD), speed=10, idle=0.4, motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        await until(pilot, lambda: app.session is not None, "the demo reads PROCESS")
        await pilot.press("x")
        assert not app.playing
        assert "Your turn" in caption_shown(app)
        first = app.workspace_root
        await until(pilot, lambda: app.rounds == 2, "the second round after the idle time")
        assert app.playing and app.workspace_root != first
        assert app.captions[-1] == "Read the setup file PROCESS."
        await until(pilot, lambda: app.session is not None, "the second round reads PROCESS again")
        app.idle = 600.0  # the restart is shown: no third round between two keys of a loaded machine
        await pilot.press("ctrl+q")  # the visitor takes over ...
        await pilot.press("ctrl+q")  # ... and, outside kiosk mode, may quit
        await until(pilot, lambda: app.return_code is not None, "the app ends on Ctrl-Q")
    assert app.return_code == 0


KEY_POOL = ([chr(c) for c in range(ord("a"), ord("z") + 1)] + [chr(c) for c in range(ord("A"), ord("Z") + 1)]
            + [str(d) for d in range(10)]
            + ["enter", "escape", "tab", "space", "ctrl+q", "ctrl+c", "question_mark", "comma", "minus",
               "full_stop", "backspace", "up", "down"]
            + ["s", "S", "y", "Y", "r", "R", "ctrl+q"] * 3)  # the quitting keys, often


@pytest.mark.slow  # CI runs it (pytest -m slow); the default run stays under 5 minutes
@sync
async def test_kiosk_survives_random_keys_and_resumes() -> None:
    app = DemoApp(ITEMS, speed=FAST, idle=0.5, kiosk=True, motion_rate=math.inf)
    rng = random.Random(1985)
    async with app.run_test(size=(80, 24)) as pilot:
        await until(pilot, lambda: app.session is not None, "the demo reads DEMO3")
        app.idle = 600.0  # no restart between two keys of a slow (loaded) test machine
        for _ in range(150):
            await pilot.press(rng.choice(KEY_POOL))
            assert app.is_running and app.return_code is None
        # S, then Y, at the MAIN MENU: the STOP key is off
        await pilot.press("escape", "escape", "r", "r")
        assert app.is_running and app.return_code is None
        assert not app.playing and app.rounds == 1
        app.idle = 0.5
        await until(pilot, lambda: app.rounds == 2, "the demo resumes after the idle time")
        assert app.playing and app.is_running
        assert app.captions.count(ITEMS[0].value) == 2  # from the start again


@sync
async def test_kiosk_keeps_the_main_menu_stop_key_off() -> None:
    app = DemoApp(parse_demo(HELD), speed=10, idle=60, kiosk=True, motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        await until(pilot, lambda: app.axes and not app.moving
                    and type(app.screen).__name__ == "MainMenuScreen", "the short script played")
        await pilot.press("x")  # take over
        assert not app.playing
        await pilot.press("s", "y", "ctrl+q")
        assert app.is_running and app.return_code is None
        assert "cannot be ended" in caption_shown(app)


@sync
async def test_the_demo_closed_mid_key_ends_quietly() -> None:
    """A kiosk stopped (or a test's run_test ended) while the demo waits for its key to be
    handled: the screens go first, and the round's next look at the screen finds none. That
    ends the round, not the app with a crash (CI's key fuzz hit it, once in many runs)."""
    app = DemoApp(ITEMS, speed=FAST, idle=600, kiosk=True, motion_rate=math.inf)
    looked: list[bool] = []

    async def press_after_the_screens_went(key: str, char: str | None = "") -> None:
        looked.append(False)
        while app.is_running or app.screen_stack:
            await asyncio.sleep(0)  # wake at every turn of the loop, as a real key's wait may
        looked.append(True)
        assert app.focused is None  # raises ScreenStackError: no screens on the stack

    app.press_demo_key = press_after_the_screens_went  # type: ignore[method-assign]
    async with app.run_test(size=(80, 24)) as pilot:
        await until(pilot, lambda: bool(looked), "the demo presses its first key")
    assert looked == [False, True] and app.crash is None


# -- valterm demo ---------------------------------------------------------------------------
@pytest.fixture
def headless(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(DemoApp, "run", functools.partialmethod(DemoApp.run, headless=True))


def test_demo_once_exits_zero(tmp_path: Path, headless: None) -> None:
    from valterm.cli import main

    script = tmp_path / "SHORT.KEYS"
    script.write_text(SHORT, encoding="utf-8")
    assert main(["demo", "--once", "--speed", "1000", "--script", str(script)]) == 0


def test_demo_with_a_bad_script_exits_one(tmp_path: Path, headless: None,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    from valterm.cli import main

    script = tmp_path / "BAD.KEYS"
    script.write_text("E\nPRESS HARDER\n", encoding="utf-8")
    assert main(["demo", "--once", "--script", str(script)]) == 1
    assert "BAD.KEYS:2: 'PRESS HARDER' is not a key" in capsys.readouterr().err
    assert main(["demo", "--speed", "0"]) == 2


def test_demo_that_fails_while_playing_exits_nonzero(tmp_path: Path, headless: None,
                                                     monkeypatch: pytest.MonkeyPatch,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    from valterm.cli import main

    async def broken(self: DemoApp, key: str) -> None:
        raise RuntimeError("the key broke")

    monkeypatch.setattr(DemoApp, "press_demo_key", broken)
    script = tmp_path / "SHORT.KEYS"
    script.write_text(SHORT, encoding="utf-8")
    assert main(["demo", "--once", "--speed", "1000", "--script", str(script)]) == 1
    assert "stopped on an error" in capsys.readouterr().err
