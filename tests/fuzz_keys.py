"""Random keys at human and machine pace, motions drawn on a stepped clock (issue 27).

    python tests/fuzz_keys.py --keys 20000            # a fresh seed, both sizes, the kiosk too
    python tests/fuzz_keys.py --keys 2000 --seed 42   # replay a seed

Every screen (VAL-II mode and the editor included) gets bursts of random keys while the
clock runs on 0.3 s a burst, so keys land while motions are drawn and screens change;
every few hundred keys a probe types ``TYPE PROBEn`` on VAL-II mode's line while a DRIVE
is drawn and checks the line ran (no key lost on the command line). The kiosk demo gets
random keys with idle resets between them. Counts: keys, probes, lost probes, crashes
(an exception that ended the app) and survived bugs (logged, the app went on). Exit 0
only when all three are 0. tests/test_fuzz_keys.py runs it with a small count.
"""

from __future__ import annotations

import argparse
import asyncio
import math
import random
import string
import tempfile
from dataclasses import dataclass, field
from pathlib import Path



from valterm.testing import Simulation
from valterm.ui.screens.main_menu import MainMenuScreen
from valterm.ui.screens.quit import QuitScreen
from valterm.ui.screens.start import StartScreen

LETTERS = [c for c in string.ascii_letters if c not in "Gg"]  # G writes exports: seconds a press
KEYS = (LETTERS + list(string.digits) + ["escape"] * 6 + ["enter"] * 6
        + ["up", "down", "left", "right", "pageup", "pagedown"] + [f"f{n}" for n in range(1, 13)]
        + ["ctrl+c", "ctrl+l", "ctrl+t", "ctrl+n", "ctrl+p", "ctrl+o", "space", "backspace", "tab",
           "question_mark", "plus", "minus", "comma", "full_stop"])
OPENERS = {"main": (), "keyboard": ("K",), "pendant": ("P",), "manipulation": ("M",), "editor": ("E",),
           "valmode": ("V",), "valline": ("V", "V"), "help": ("question_mark",), "start": ("B",)}
BURST_GAP = 0.3  # clock seconds between bursts: motions are still drawn when the next keys come
PROBE_EVERY = 400


@dataclass
class Tally:
    keys: int = 0
    probes: int = 0
    lost: list[str] = field(default_factory=list)
    crashes: list[str] = field(default_factory=list)
    survived: list[str] = field(default_factory=list)

    @property
    def clean(self) -> bool:
        return not (self.lost or self.crashes or self.survived)


async def go_home(sim: Simulation) -> bool:
    """ESC (N to a save question, E RETURN at the start) until MAIN waits; False if never."""
    for _ in range(60):
        await sim.settle(step=2.0, limit=200)
        await sim.pilot.pause(0.05)
        screen = sim.screen
        if isinstance(screen, MainMenuScreen) and not sim.prompt():
            return True
        if isinstance(screen, QuitScreen):
            await sim.press("N")
        elif isinstance(screen, StartScreen) and not sim.prompt():
            await sim.press("E", "enter")
        elif "SAVE" in sim.prompt() or getattr(screen, "mode", "") == "save?":
            await sim.press("N")
        else:
            await sim.press("escape")
    return False


async def probe(sim: Simulation, n: int, tally: Tally) -> None:
    """DRIVE, then TYPE PROBEn typed on VAL-II mode's line while the DRIVE is drawn: both
    must run, each whole."""
    if not await go_home(sim):
        return
    await sim.press("V", "v")  # VAL-II mode's menu, then its command line
    await sim.pilot.pause(0.05)
    await sim.burst(*"DRIVE 1,5,10", "enter", *f"TYPE PROBE{n}", "enter")
    tally.probes += 1
    await sim.settle(step=0.5, limit=400)
    for _ in range(50):
        if not getattr(sim.app, "keys_waiting", 0):
            break
        await sim.advance(0.5)
    transcript = list(getattr(sim.screen, "transcript", []))
    if f"PROBE{n}" not in transcript or ". DRIVE 1,5,10" not in transcript:
        tally.lost.append(f"probe {n}: {transcript[-4:]}")


async def fuzz_app(seed: int, count: int, size: tuple[int, int], tally: Tally) -> None:
    rng = random.Random(seed)
    with tempfile.TemporaryDirectory(prefix="valterm-fuzz-") as folder:
        async with Simulation(Path(folder) / "ws", size=size, animate=True, rate=10.0) as sim:
            sim.app.exit = lambda *args, **kwargs: None  # S Y and CTRL-Q stay in
            pressed, next_probe = 0, rng.randint(20, 120)
            names = list(OPENERS)
            while pressed < count:
                name = rng.choice(names)
                if not await go_home(sim):
                    tally.crashes.append(f"seed {seed} {size}: ESC never led to MAIN from {name}")
                    return
                await sim.burst(*OPENERS[name])
                for _ in range(rng.randint(3, 12)):
                    keys = [rng.choice(KEYS) for _ in range(1 if rng.random() < 0.4 else rng.randint(2, 20))]
                    await sim.burst(*keys)
                    sim.clock.advance(BURST_GAP)
                    await sim.pilot.pause(0.01)
                    pressed += len(keys)
                    if not sim.app.is_running or sim.app.crash is not None:
                        tally.crashes.append(f"seed {seed} {size} on {name}: {sim.app.crash!r}")
                        return
                if pressed >= next_probe:
                    next_probe += PROBE_EVERY
                    await probe(sim, pressed, tally)
            tally.keys += pressed
            tally.survived += [f"seed {seed} {size}: {line}" for line in sim.app.survived]


async def fuzz_kiosk(seed: int, count: int, tally: Tally) -> None:
    from valterm.core.files.demokeys import load_demo
    from valterm.ui.demo import DemoApp

    rng = random.Random(seed)
    app = DemoApp(load_demo(), speed=1000.0, idle=0.3, kiosk=True, motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        pressed = 0
        while pressed < count:
            keys = [rng.choice(KEYS) for _ in range(rng.randint(1, 10))]
            await pilot.press(*keys)
            pressed += len(keys)
            if rng.random() < 0.1:
                await asyncio.sleep(0.5)  # the idle reset, often mid-screen and mid-motion
            if not app.is_running or app.crash is not None:
                tally.crashes.append(f"kiosk seed {seed}: {app.crash!r}")
                return
        tally.keys += pressed
        tally.survived += [f"kiosk seed {seed}: {line}" for line in app.survived]


async def run(seed: int, keys: int, kiosk_share: float = 0.1) -> Tally:
    tally = Tally()
    kiosk = int(keys * kiosk_share)
    half = (keys - kiosk) // 2
    await fuzz_app(seed, half, (80, 24), tally)
    await fuzz_app(seed + 1, keys - kiosk - half, (160, 50), tally)
    if kiosk:
        await fuzz_kiosk(seed + 2, kiosk, tally)
    return tally


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keys", type=int, default=20_000)
    parser.add_argument("--seed", type=int, default=None)
    args = parser.parse_args(argv)
    seed = args.seed if args.seed is not None else random.SystemRandom().randrange(2**32)
    tally = asyncio.run(run(seed, args.keys))
    print(f"seed {seed}: {tally.keys} keys, {tally.probes} probes, {len(tally.lost)} lost, "
          f"{len(tally.crashes)} crashes, {len(tally.survived)} survived bugs")
    for line in tally.lost + tally.crashes + tally.survived:
        print("  " + line)
    return 0 if tally.clean else 1


if __name__ == "__main__":
    raise SystemExit(main())
