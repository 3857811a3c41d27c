"""The one event player (ui/playback.py) in the app: runaway programs keep the screen alive,
CTRL-C is seen at the next tick, the transcript stays capped, and VAL-II mode, ``valterm run``
and the core's renderer print the same lines for the same program."""

from __future__ import annotations

import math
import time
from collections.abc import AsyncIterator, Iterator
from contextlib import asynccontextmanager
from typing import Any
from pathlib import Path

import pytest

from app_helpers import FakeClock, screen_text, sync, until
from valterm.core.errors import ValtermError
from valterm.core.events import Event, Message, TypeOut
from valterm.core.session import Session
from valterm.core.text.transcript import event_lines
from valterm.core.val.limits import NO_LIMITS
from valterm.ui.app import ValtermApp
from valterm.ui.playback import LOG_CACHE, LOG_LINES, TRANSCRIPT_LINES
from valterm.ui.screens.keyboard import KeyboardScreen
from valterm.ui.screens.valmode import Mode, ValModeScreen


class Host(ValtermApp):
    """The app on a session; the test pushes VAL-II mode itself."""

    def __init__(self, session: Session, **kwargs) -> None:  # type: ignore[no-untyped-def]
        super().__init__(session=session, **kwargs)

    def on_mount(self) -> None:
        pass


async def typed(pilot, text: str) -> None:  # type: ignore[no-untyped-def]
    await pilot.press(*text, "enter")


async def valmode(app: ValtermApp, pilot) -> ValModeScreen:  # type: ignore[no-untyped-def]
    screen = ValModeScreen(show_menu=False)
    await app.push_screen(screen)
    await pilot.pause()
    return screen


async def run_until(pilot, done) -> None:  # type: ignore[no-untyped-def]
    """Until ``done()``: bounded by app_helpers.until's guard, not by a count of pauses (a
    loaded machine needs more of them)."""
    await until(pilot, done, "the player's state")


def session_with(tmp_path: Path, programs: dict[str, str]) -> Session:
    session = Session(workspace_root=tmp_path / "ws")
    for name, text in programs.items():
        (session.workspace.root / f"{name}.DAT").write_text(text)
    return session


@pytest.mark.parametrize("program", ["10  GOTO 10\n", '10  TYPE "AGAIN"\n    GOTO 10\n'])
@sync
async def test_a_runaway_program_keeps_the_screen_alive_and_ctrl_c_stops_it(tmp_path: Path, program: str) -> None:
    """EXECUTE of a loop with no motion and no DELAY: ticks go on, the screen shows the
    steps, CTRL-C is seen at the next tick, and the command line answers afterwards.

    The ticks after CTRL-C are counted with the player's real-time clock being the app's own
    CPU time: a tick also ends after TICK_LIMIT of real time, so on a loaded machine (CI's
    four workers on two cores) a tick preempted for 25 ms before it pulled the program's
    ABORTED ended with nothing done and the count was 2, a fact about the scheduler, not the
    app. The real-time limit has its own test (test_a_tick_works_its_budget_of_cpu_...)."""
    session = session_with(tmp_path, {"SPIN": program})
    session.limits = NO_LIMITS  # it runs until CTRL-C (the app's run limits: tests/test_run_limits.py)
    app = Host(session, motion_rate=10.0, clock=FakeClock())
    async with app.run_test(size=(120, 40)) as pilot:
        screen = await valmode(app, pilot)
        await typed(pilot, "EXEC SPIN")
        player = app.player
        first = player.ticks
        # the pump hands the loop back to Textual tick after tick (a pump that did not would
        # never let this coroutine run again)
        await run_until(pilot, lambda: player.ticks - first >= 5 and len(screen.transcript) == TRANSCRIPT_LINES)
        assert screen.mode == Mode.RUNNING and player.playing
        assert "SPIN" in screen_text(app) and "GOTO 10" in screen_text(app)  # the screen was drawn
        assert len(screen.transcript) == TRANSCRIPT_LINES  # capped: memory stays flat
        assert len(screen.query_one("#val-log").lines) <= LOG_LINES

        player.real_time = time.thread_time  # between ticks: the next one starts on it
        await pilot.press("ctrl+c")
        await run_until(pilot, lambda: not player.playing)
        assert player.end_tick - player.abort_tick <= 1  # seen at the next tick (a few ms)
        assert screen.transcript[-1].startswith("*** SPIN STEP") and screen.transcript[-1].endswith("ABORTED")
        assert screen.mode == Mode.COMMAND and not app.session.program_running
        await typed(pilot, "WHERE")  # the line stayed open: no C first
        await run_until(pilot, lambda: screen.mode == Mode.COMMAND)
        assert any(line.startswith("OPENED") for line in list(screen.transcript)[-4:])


@sync
async def test_ctrl_c_while_paused_aborts_and_delay_waits_on_the_clock(tmp_path: Path) -> None:
    clock = FakeClock()
    program = "    PAUSE\n    DELAY 5\n    TYPE \"LATE\"\n"
    app = Host(session_with(tmp_path, {"WAIT": program}), motion_rate=10.0, clock=clock)
    async with app.run_test(size=(120, 40)) as pilot:
        screen = await valmode(app, pilot)
        await typed(pilot, "EXEC WAIT")
        assert screen.mode == Mode.PAUSED and app.player.paused
        await typed(pilot, "PROCEED")
        await pilot.pause(0.1)
        assert app.player.playing and screen.transcript[-1] == "WAIT        2  DELAY 5"  # on the test's clock
        clock.t += 5.0
        await run_until(pilot, lambda: not app.player.playing)
        assert screen.transcript[-1] == "PROGRAM WAIT COMPLETED: 1 LOOP" and screen.mode == Mode.COMMAND

        await typed(pilot, "EXEC WAIT")
        assert screen.mode == Mode.PAUSED
        await pilot.press("ctrl+c")
        await run_until(pilot, lambda: not app.player.playing)
        assert screen.transcript[-1] == "*** WAIT STEP 2: ABORTED" and screen.mode == Mode.COMMAND


def _refused() -> Iterator[Event]:
    raise ValtermError("no such thing here")
    yield Message("never")


def _buggy() -> Iterator[Event]:
    yield TypeOut("BEFORE")
    raise RuntimeError("a bug in the core")


@sync
async def test_refusals_are_shown_and_bugs_logged(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    logs = tmp_path / "state" / "valterm"
    app = Host(Session(workspace_root=tmp_path / "ws"), motion_rate=math.inf)
    async with app.run_test(size=(120, 40)) as pilot:
        screen = KeyboardScreen()
        await app.push_screen(screen)
        await pilot.pause()
        app.run_events(_refused(), screen)
        await pilot.pause()
        assert "NO SUCH THING HERE" in screen.messages.text and not logs.exists()
        app.run_events(_buggy(), screen)
        await pilot.pause()
        shown = screen.messages.text.splitlines()
        [log] = logs.glob("crash-*.log")  # the one crash log of the CLI and the app
        assert shown[-2:] == ["BEFORE", f"*** INTERNAL ERROR (RUNTIMEERROR: A BUG IN THE CORE); SEE {log}"]
        assert "Traceback" in log.read_text() and "_buggy" in log.read_text()
        assert not app.player.playing


@sync
async def test_a_flood_of_lines_keeps_the_last_ones(tmp_path: Path) -> None:
    app = Host(Session(workspace_root=tmp_path / "ws"), motion_rate=math.inf)
    async with app.run_test(size=(120, 40)) as pilot:
        screen = await valmode(app, pilot)
        screen.run_events(iter([TypeOut(f"LINE {i}") for i in range(50_000)]))  # asked of the app
        await run_until(pilot, lambda: not app.moving and screen.mode == Mode.COMMAND)  # its end seen
        assert list(screen.transcript) == [f"LINE {i}" for i in range(48_000, 50_000)]
        log = screen.query_one("#val-log")
        assert len(log.lines) == LOG_LINES and log.lines[-1].text == "LINE 49999"
        # what the log holds of the lines it drew is capped too (memory levels off in minutes)
        for y in range(0, LOG_LINES, 10):  # every line of it drawn, a page at a time
            log.scroll_to(y=y, animate=False)
            await pilot.pause()
        assert 0 < len(log._line_cache) <= LOG_CACHE < LOG_LINES


def _transcript_of_run(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> list[str]:
    from valterm.cli import main

    assert main(["--workspace", str(tmp_path / "run"), "run", "PROCESS", "--cell", "PROCESS", "--loc", "PROCESS"]) == 0
    out = capsys.readouterr().out.splitlines()
    return out[: out.index("WHERE") - 1]  # the final WHERE and VARIABLES are run's own


def _transcript_of_renderer(tmp_path: Path) -> list[str]:
    session = Session(workspace_root=tmp_path / "core", setup="PROCESS")
    session.load_locations("PROCESS")
    return [line for event in session.interpreter.execute("PROCESS") for line in event_lines(event)]


def test_valmode_run_and_the_renderer_print_the_same_lines(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    by_run = _transcript_of_run(tmp_path, capsys)
    by_renderer = _transcript_of_renderer(tmp_path)
    session = Session(workspace_root=tmp_path / "app", setup="PROCESS")
    session.load_locations("PROCESS")
    app = Host(session, motion_rate=math.inf)
    seen: list[str] = []

    async def body() -> None:
        async with app.run_test(size=(120, 40)) as pilot:
            screen = await valmode(app, pilot)
            await typed(pilot, "EXECUTE PROCESS")
            await run_until(pilot, lambda: screen.mode == Mode.COMMAND)
            seen.extend(screen.transcript)

    sync(body)()
    assert seen[0] == ". EXECUTE PROCESS"
    assert seen[1:] == by_run == by_renderer
    assert "PROCESS     6  APPRO A, -50" in by_run and "PROGRAM PROCESS COMPLETED: 1 LOOP" in by_run


@sync
async def test_a_command_at_a_menu_stops_a_running_loop_first(tmp_path: Path) -> None:
    """V at KEYBOARD: EXECUTE of a loop, then another command: the loop is aborted, not
    skipped to an end it does not have."""
    app = Host(session_with(tmp_path, {"SPIN": "10  GOTO 10\n"}), motion_rate=math.inf)
    async with app.run_test(size=(120, 40)) as pilot:
        screen = KeyboardScreen()
        await app.push_screen(screen)
        await pilot.pause()
        screen.run_command("EXECUTE SPIN")
        await pilot.pause(0.1)
        assert app.player.playing and app.session.program_running
        screen.run_command("WHERE")
        await run_until(pilot, lambda: not app.player.playing)
        said = [line for line, _ in screen.messages.lines]  # all of this turn; three show at once
        assert "*** SPIN STEP 1: ABORTED" in said and "NOFLIP" in said[-1]
        assert not app.session.program_running


class _TickClocks:
    """A tick's real time and CPU time, moved by the events the source makes (test_…_load)."""

    def __init__(self) -> None:
        self.real = self.cpu = 0.0


class _Screen:
    """What the player posts (ui.messages), kept."""

    def __init__(self) -> None:
        self.lines: list[str] = []
        self.ended = False

    def post(self, message: object) -> None:
        from valterm.ui.messages import RunEnded, TranscriptLines

        if isinstance(message, TranscriptLines):
            self.lines.extend(message.lines)
        self.ended = self.ended or isinstance(message, RunEnded)


def _events_costing(clocks: _TickClocks, real: float, cpu: float, count: int) -> Iterator[Event]:
    for i in range(count):
        clocks.real += real
        clocks.cpu += cpu
        yield TypeOut(f"LINE {i}")


@pytest.mark.parametrize(("cpu_share", "most_ticks", "fewest_ticks"), [(1.0, 54, 48), (0.05, 14, 10)])
@sync
async def test_a_tick_works_its_budget_of_cpu_whatever_the_load(tmp_path: Path, cpu_share: float,
                                                                most_ticks: int, fewest_ticks: int) -> None:
    """A tick's budget (5 ms) is the app's own CPU time: on a loaded machine, where other
    processes take most of the real time, a tick still does its share of work (up to 25 ms of
    real time), instead of ever more ticks, each with its redraw, doing ever less. 300 events of
    1 ms real time each: with all of it CPU, a tick ends after 6 (the first past its 5 ms); with
    5 % of it, after 26 (the first past 25 ms of real time): about 50 ticks against 12."""
    from valterm.ui.playback import Player

    app = Host(Session(workspace_root=tmp_path / "ws"), motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        clocks = _TickClocks()
        player = Player(app, rate=math.inf, real_time=lambda: clocks.real, cpu_time=lambda: clocks.cpu)
        audience = _Screen()
        player.play(_events_costing(clocks, 0.001, 0.001 * cpu_share, 300), audience.post)
        await run_until(pilot, lambda: not player.playing)
        assert audience.ended and audience.lines == [f"LINE {i}" for i in range(300)]
        assert fewest_ticks <= player.ticks <= most_ticks


@sync
async def test_a_tick_preempted_before_its_first_event_still_takes_one(tmp_path: Path) -> None:
    """A tick takes at least one event whatever the clock says: a machine so loaded that every
    tick is preempted past TICK_LIMIT before it pulls anything still plays the stream, an
    event a tick (it used to do nothing, tick after tick: D_DEFINE's move never ended)."""
    from valterm.ui.playback import TICK_LIMIT, Player

    app = Host(Session(workspace_root=tmp_path / "ws"), motion_rate=math.inf)
    async with app.run_test(size=(80, 24)) as pilot:
        clocks = _TickClocks()

        def preempted() -> float:
            clocks.real += 2 * TICK_LIMIT  # each look at the clock comes after a preemption
            return clocks.real

        player = Player(app, rate=math.inf, real_time=preempted, cpu_time=lambda: clocks.cpu)
        audience = _Screen()
        player.play(_events_costing(clocks, 0.0, 0.0, 20), audience.post)
        await until(pilot, lambda: not player.playing, "the stream's end", limit=10.0)
        assert audience.ended and audience.lines == [f"LINE {i}" for i in range(20)]
        assert player.ticks == 21  # one event a tick, the end the 21st


@asynccontextmanager
async def swinging(tmp_path: Path, clock: FakeClock) -> AsyncIterator[tuple[Host, Any, ValModeScreen]]:
    """The app, its pilot and VAL-II mode running a program that swings JT1 to and fro for
    ever, a motion being drawn: paced by ``clock``, drawn until the test moves it on."""
    session = session_with(tmp_path, {"SWING": "10  DRIVE 1,20,100\n    DRIVE 1,-20,100\n    GOTO 10\n"})
    session.limits = NO_LIMITS
    app = Host(session, motion_rate=10.0, clock=clock)
    async with app.run_test(size=(120, 40)) as pilot:
        screen = await valmode(app, pilot)
        await typed(pilot, "EXEC SWING")
        await run_until(pilot, lambda: app.player.drawing)
        yield app, pilot, screen


@sync
async def test_esc_aborts_a_never_ending_program_with_keys_typed_before_it(tmp_path: Path) -> None:
    """The RUNNING key line says CTRL-C OR ESC: ABORT. A key typed while the program moves
    waits for the motion (ui.keyqueue), and a program of motions back to back never lets it
    go: ESC typed after it waited behind it, and the program ran on until CTRL-C. ESC now
    aborts as CTRL-C does, the keys typed during the run dropped with it (F8 here: the model
    is not toggled after the abort)."""
    clock = FakeClock()
    async with swinging(tmp_path, clock) as (app, pilot, screen):
        assert "ABORT" in screen.keys_text, screen.keys_text
        model_only = screen.model_only
        await pilot.press("f8")          # waits: a motion is drawn
        assert app.keys_waiting == 1
        await pilot.press("escape")
        await until(pilot, lambda: not app.player.playing, "the program's end", between=lambda: clock.advance(0.05))
        assert screen.transcript[-1].startswith("*** SWING STEP") and screen.transcript[-1].endswith("ABORTED")
        await pilot.pause(0.05)
        assert app.keys_waiting == 0 and screen.model_only == model_only


@sync
async def test_text_typed_while_a_program_moves_shows_in_the_line_at_once(tmp_path: Path) -> None:
    """KEYS TYPED NOW GO TO THE LINE: while the motions of a never-ending program are drawn
    the line shows what is typed, RETURN queues it (QUEUED: WHERE), and CTRL-C discards it.
    A key that is no text (F8) still waits for the motion, and text typed after it waits
    behind it (the order kept). Before, all of it waited until the program ended."""
    clock = FakeClock()
    async with swinging(tmp_path, clock) as (app, pilot, screen):
        line = screen.query_one("#val-line")
        await pilot.press(*"WHEREX", "backspace")
        assert app.player.drawing and app.keys_waiting == 0 and line.value == "WHERE"
        await pilot.press("enter")
        await run_until(pilot, lambda: "QUEUED: WHERE" in screen.transcript)
        assert app.player.drawing and line.value == ""
        await pilot.press("f8", "M")
        assert app.keys_waiting == 2 and line.value == ""
        await pilot.press("ctrl+c")
        await until(pilot, lambda: not app.player.playing, "the program's end", between=lambda: clock.advance(0.05))
        await run_until(pilot, lambda: any("QUEUED COMMAND DISCARDED: WHERE" in t for t in screen.transcript))
