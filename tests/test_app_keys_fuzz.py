"""Random keys on every menu screen at 80x24 and 160x50 (issue 17, "make the class impossible").

Thousands of keys (letters, digits, ESC, RETURN, arrows, F-keys, CTRL-C, pasted text) are
pressed from each screen; nothing may raise, and afterwards ESC (answering N to a save
question, E RETURN on the start screen) must always lead back to the MAIN MENU. One run
uses a fixed seed, one a fresh seed that is printed (``-s`` shows it; a failure names it).
"""

from __future__ import annotations

import asyncio
import random
import string
import time
from pathlib import Path

import pytest

from valterm.testing import Simulation
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.screens.quit import QuitScreen
from valterm.ui.screens.start import StartScreen

# G (GENERATE) writes OBJ and GLB exports, two seconds a press: it is tested on its own
LETTERS = [c for c in string.ascii_letters if c not in "Gg"]
KEYS = (
    LETTERS + list(string.digits)
    + ["escape"] * 6 + ["enter"] * 6 + ["up", "down", "left", "right", "pageup", "pagedown"]
    + [f"f{n}" for n in range(1, 13)]
    + ["ctrl+c", "space", "backspace", "tab", "question_mark", "plus", "minus", "comma", "full_stop"]
)
PASTES = ["MOVE A", "LISTF", "1", "HERE P1", "EDIT TEST", " 10 TYPE HELLO", "ZZZ\nQQQ", ""]
# the screens, as the keys that open them from MAIN
OPENERS = {"main": (), "keyboard": ("K",), "pendant": ("P",), "manipulation": ("M",),
           "editor": ("E",), "help": ("question_mark",), "start": ("B",)}
KEYS_PER_SCREEN = 80  # a fixed count: a seed replays exactly
BUDGET = 240.0  # a safety cap only (a very slow machine, loaded); normally every key is pressed


async def go_home(sim: Simulation, seed: int, where: str) -> None:
    """ESC (and the answers that leave without saving) until the MAIN MENU waits for a key."""
    for _ in range(40):
        screen = sim.screen
        if isinstance(screen, MainMenuScreen) and not sim.prompt():
            return
        if isinstance(screen, QuitScreen):
            await sim.press("N")
        elif isinstance(screen, StartScreen) and not sim.prompt():
            await sim.press("E", "enter")
        elif "SAVE" in sim.prompt() or getattr(screen, "mode", "") == "save?":
            await sim.press("N")  # leave without saving (the save question itself is tested elsewhere)
        else:
            await sim.press("escape")
    stack = [type(s).__name__ for s in sim.app.screen_stack]
    raise AssertionError(f"seed {seed}: ESC did not lead back to MAIN from {where} ({stack}):\n{sim.text()}")


async def fuzz(tmp_path: Path, seed: int, size: tuple[int, int]) -> int:
    rng = random.Random(seed)
    pressed = 0
    async with Simulation(tmp_path / f"ws{size[0]}", size=size) as sim:
        exits: list[object] = []
        sim.app.exit = lambda *args, **kwargs: exits.append(args)  # S Y and CTRL-Q stay in
        stop = time.monotonic() + BUDGET
        for name, opener in OPENERS.items():
            await go_home(sim, seed, "the start")
            await sim.press(*opener)
            pressed_here = 0
            while pressed_here < KEYS_PER_SCREEN and time.monotonic() < stop:
                if rng.random() < 0.05:
                    await sim.paste(rng.choice(PASTES))
                    pressed_here += 1
                else:  # one key (a slow typist) or many at once (a fast one, type-ahead)
                    count = 1 if rng.random() < 0.2 else rng.randint(2, 40)
                    keys = [rng.choice(KEYS) for _ in range(count)]
                    await sim.burst(*keys)
                    pressed_here += len(keys)
                assert sim.app.is_running, f"seed {seed}: the app stopped on {name}"
            pressed += pressed_here
            await go_home(sim, seed, name)
            assert "MAIN MENU" in sim.text() or sim.screen.model_shown
    return pressed


@pytest.mark.slow  # CI runs it (pytest -m slow); the default run stays under 5 minutes
@pytest.mark.parametrize("size", [(80, 24), (160, 50)], ids=["80x24", "160x50"])
def test_random_keys_fixed_seed(tmp_path: Path, size: tuple[int, int]) -> None:
    assert asyncio.run(fuzz(tmp_path, 1985, size)) >= 7 * KEYS_PER_SCREEN


@pytest.mark.slow  # CI runs it (pytest -m slow); the default run stays under 5 minutes
def test_random_keys_fresh_seed(tmp_path: Path) -> None:
    seed = random.SystemRandom().randrange(2**32)
    print(f"random-key seed {seed}")
    size = random.Random(seed).choice([(80, 24), (160, 50)])
    assert asyncio.run(fuzz(tmp_path, seed, size)) >= 7 * KEYS_PER_SCREEN, f"seed {seed}"
