"""Issue 25 (start time): what the app loads before MAIN MENU. The heavy readers and checkers
load when first used; each is still there when asked for."""

from __future__ import annotations

import ast
import json
import os
import subprocess
import sys

from app_helpers import until

HEAVY = ("trimesh", "fcl", "valterm.core.cad.iges", "valterm.core.cad.iges_entities",
         "valterm.core.val.interpreter", "valterm.core.val.debugger", "valterm.core.val.dialects.vplus")


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


def test_the_session_starts_without_json_and_the_collision_scene_and_each_loads_when_used() -> None:
    """json (``run --json``) and the collision scene (the first check) are not loaded by the
    app's modules and a session's start; each is there when first used."""
    probe = ("import sys, tempfile\n"
             "import valterm.cli, valterm.ui.app\n"
             "from valterm.core.events import Message\n"
             "from valterm.core.session import Session\n"
             "s = Session(tempfile.mkdtemp(), setup='PROCESS')\n"
             "s.simulator.robot_polyhedra()\n"
             "before = sorted(m for m in ('json', 'valterm.core.collision.frames') if m in sys.modules)\n"
             "line = Message('HELLO').json_line()\n"
             "found = list(s.simulator.check_collisions())\n"
             "after = sorted(m for m in ('json', 'valterm.core.collision.frames') if m in sys.modules)\n"
             "print(repr((before, line, after)))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    before, line, after = ast.literal_eval(out.stdout.strip().splitlines()[-1])
    assert before == []
    assert json.loads(line) == {"event": "message", "text": "HELLO", "level": "info"}
    assert after == ["json", "valterm.core.collision.frames"]


def test_each_loads_when_first_used() -> None:
    # the CAD package's face loads none of its modules: each is imported where it is used
    assert _loaded("import valterm.core.cad") == []
    code = ("import tempfile\n"
            "from valterm.core.cad.iges import read_iges\n"
            "from valterm.core.session import Session\n"
            "Session(tempfile.mkdtemp()).interpreter")
    assert {"valterm.core.cad.iges", "valterm.core.val.interpreter"} <= set(_loaded(code))


# what MAIN MENU does not show loads when its key is pressed (issue 25: the start)
NOT_AT_MAIN_MENU = ("valterm.ui.screens.editor", "valterm.ui.screens.valmode", "valterm.ui.screens.keyboard",
                    "valterm.ui.screens.manipulation", "valterm.ui.screens.pendant", "valterm.ui.screens.help",
                    "valterm.ui.screens.start", "valterm.ui.hardcopy", "valterm.core.cad.export",
                    "valterm.core.cad.convert", "valterm.core.editor", "valterm.core.val.compiler",
                    "concurrent.futures.process", "valterm.core.files.vplus", "valterm.ui.widgets.transcript_log", "rich.pretty", "importlib.resources", "importlib.metadata",
                    "valterm.core.collision.frames", "valterm.core.collision.thesis", "valterm.core.collision.world",
                    *HEAVY)

MAIN_MENU_PROBE = """
import asyncio, json, sys, tempfile
import valterm.cli
from valterm.ui.app import ValtermApp

async def main():
    app = ValtermApp(tempfile.mkdtemp(), "PROCESS")
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        shown = type(app.screen).__name__
        loaded = sorted(m for m in {names!r} if m in sys.modules)
        parts = len(app.session.simulator.cell.objects)
        await pilot.press("v")
        await pilot.pause()
        print(json.dumps([shown, loaded, parts, type(app.screen).__name__, "valterm.ui.screens.valmode" in sys.modules]))

asyncio.run(main())
"""


def test_main_menu_shows_without_the_modes_screens_and_each_loads_on_its_key() -> None:
    probe = MAIN_MENU_PROBE.format(names=NOT_AT_MAIN_MENU)
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    shown, loaded, parts, after_v, valmode_loaded = json.loads(out.stdout.strip().splitlines()[-1])
    assert (shown, loaded, parts) == ("MainMenuScreen", [], 14)
    assert (after_v, valmode_loaded) == ("ValModeScreen", True)


def test_the_keymap_file_still_checks_every_screens_ids(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """The binding ids come from every screen: with a keymap file they are all loaded then."""
    from valterm.core.errors import ValtermError
    from valterm.core.files.keymapfile import KEYMAP_ENV
    from valterm.ui.bindings import load_user_keymap

    keymap = tmp_path / "keymap.toml"
    monkeypatch.setenv(KEYMAP_ENV, str(keymap))
    keymap.write_text('"editor.create" = "f12"\n', encoding="utf-8")  # an id of a screen MAIN MENU does not load
    assert load_user_keymap() == {"editor.create": "f12"}
    keymap.write_text('"editor.no_such_key" = "f12"\n', encoding="utf-8")
    try:
        load_user_keymap()
    except ValtermError as error:
        assert "no binding id" in str(error)
    else:
        raise AssertionError("an unknown binding id was accepted")


def test_the_apps_command_line_loads_no_commands_module() -> None:
    """`valterm --setup PROCESS` parses its options without any subcommand's module (issue 25);
    a subcommand's line loads its own module only."""
    probe = ("import json, sys\nfrom valterm.cli import build_parser, chosen_commands\n"
             "def parsed(argv):\n"
             "    build_parser(chosen_commands(argv)).parse_args(argv)\n"
             "    return sorted(m for m in sys.modules if m.startswith('valterm.commands.'))\n"
             "print(json.dumps([parsed(['--setup', 'PROCESS', '--rules', '1985']), parsed(['check', 'X'])]))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    app_line, check_line = json.loads(out.stdout.strip().splitlines()[-1])
    assert app_line == ["valterm.commands.limits", "valterm.commands.robots"]  # the app's own options
    assert check_line == ["valterm.commands.check", *app_line]


def test_the_command_line_keeps_numpys_blas_to_one_thread() -> None:
    """OpenBLAS's threads spin at numpy's import, taking CPU from the app's start on a busy
    machine (issue 25): the command line sets one thread before numpy loads, unless the user
    set a number."""
    probe = ("import os, sys\nfrom valterm.cli import main\nassert 'numpy' not in sys.modules\n"
             "assert main(['kin', 'fk', '0', '0', '0', '0', '0', '0']) == 0 and 'numpy' in sys.modules\n"
             "status = open('/proc/self/status').read() if os.path.exists('/proc/self/status') else ''\n"
             "threads = [line.split()[1] for line in status.splitlines() if line.startswith('Threads:')]\n"
             "print(os.environ['OPENBLAS_NUM_THREADS'], threads[0] if threads else '1')")
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True, env=env)
    assert out.stdout.split()[-2:] == ["1", "1"]
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True,
                         env={**env, "OPENBLAS_NUM_THREADS": "2"})
    assert out.stdout.split()[-2] == "2"


GC_PROBE = """
import gc, json, sys, tempfile
from valterm.ui import app as ui_app
from valterm.cli import main
seen = []
def run(self, *args, **kwargs):
    seen.append([gc.isenabled(), self.collect_after_first_frame])
    return 0
ui_app.ValtermApp.run = run
seen.append(main(["--workspace", tempfile.mkdtemp(), "--setup", "PROCESS"]))
seen.append(gc.isenabled())
seen.append(main(["kin", "fk", "0", "0", "0", "0", "0", "0"]))
seen.append(gc.isenabled())
print(json.dumps(seen))
"""


def test_the_collector_waits_for_the_apps_first_frame_only() -> None:
    """The command line pauses Python's cycle collector for the start (issue 25); the app is
    told to turn it on after its first frame, and it is on again when main returns."""
    out = subprocess.run([sys.executable, "-c", GC_PROBE], capture_output=True, text=True, check=True)
    assert json.loads(out.stdout.strip().splitlines()[-1]) == [[False, True], 0, True, 0, True]


async def test_the_app_turns_the_collector_on_after_its_first_frame(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """On again after the first frame (with --setup, the one with the picture, once the
    set-up is read), with the start's objects frozen out of it: its first pass would
    otherwise walk them all while the frame waits to be written."""
    import gc

    from valterm.ui.app import ValtermApp

    app = ValtermApp(tmp_path, "PROCESS")
    app.collect_after_first_frame = True
    gc.unfreeze()
    gc.disable()
    try:
        async with app.run_test(size=(160, 50)) as pilot:
            await until(pilot, gc.isenabled, "the collector on after the first frame")
            assert type(app.screen).__name__ == "MainMenuScreen"
            assert gc.isenabled() and app.session_read is not None
            frozen = gc.get_freeze_count()
            assert frozen > 10_000  # the start's objects (Textual's, the session's, the screen's)
            assert id(app.screen) not in {id(o) for o in gc.get_objects()}  # MAIN MENU is frozen
    finally:
        gc.unfreeze()  # the rest of the tests' process as it was
        gc.enable()


def test_the_workspace_knows_the_v_plus_files_without_their_reader() -> None:
    """The workspace lists .V2 / .PG files without loading the V+ reader (issue 25, the start):
    its kinds are the reader's extensions, and a V+ name loads it."""
    from valterm.core import workspace
    from valterm.core.files import vplus

    assert tuple(ext.lstrip(".") for ext in vplus.EXTENSIONS) == workspace.VPLUS_KINDS
    assert workspace._vplus() is vplus


async def test_main_menu_draws_its_picture_once_each_time_it_is_shown_again(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """Textual runs every class's on_screen_resume along the MRO: MAIN MENU's own does not
    call MenuScreen's as well, and the mount leaves the drawing to the resume (the picture
    was built three times at the start, issue 25). First shown, it is drawn blank by its
    resume and with the picture once the set-up is read: one picture rasterized."""
    from valterm.ui.app import ValtermApp
    from valterm.ui.screens.base import MenuScreen

    drawn: list[str] = []
    redraw = MenuScreen.redraw
    monkeypatch.setattr(MenuScreen, "redraw", lambda self: drawn.append(type(self).__name__) or redraw(self))
    app = ValtermApp(tmp_path, "PROCESS")
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        await pilot.pause()
        assert drawn == ["MainMenuScreen"] * 2  # its resume (blank), the set-up read; not its mount
        assert app.screen.model_view.redraws == 1
        await pilot.press("k")
        await pilot.pause()
        drawn.clear()
        await pilot.press("escape")  # KEYBOARD -> MAIN MENU
        await pilot.pause()
        assert type(app.screen).__name__ == "MainMenuScreen"
        assert drawn == ["MainMenuScreen"]
        assert "SETUP FILE PROCESS.SET WITH 14 PARTS" in app.screen.messages.text


PARSE_PROBE = """
import contextlib, io, json, sys
from valterm.cli import build_parser, chosen_commands, parse_command_line

def outcome(parse, argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            result = sorted(vars(parse(argv)).items())
        except SystemExit as done:
            result = ["exit", done.code]
    return [repr(result), out.getvalue(), err.getvalue()]

lines = [[], ["--setup", "PROCESS"], ["--workspace", "W", "--setup", "PROCESS", "--rules", "controller"],
         ["--robot", "PUMA560", "--ascii", "--keys", "1985"], ["--robot", "NOPE"], ["--setup"], ["--nope"],
         ["--help"], ["-h"], ["--he"], ["--version"], ["--setup", "run"], ["check", "X"], ["--rules", "1999"],
         ["--max-steps", "10"], ["X"]]
long_way = lambda argv: build_parser(chosen_commands(argv)).parse_args(argv)
print(json.dumps([[outcome(parse_command_line, a), outcome(long_way, a)] for a in lines]))
"""


def test_the_apps_line_is_parsed_as_the_long_way_parses_it() -> None:
    """An app's line skips the glance (issue 25, the start): every line parses, and every help
    or usage error reads, as through the glance and every command it names."""
    out = subprocess.run([sys.executable, "-c", PARSE_PROBE], capture_output=True, text=True, check=True)
    pairs = json.loads(out.stdout.strip().splitlines()[-1])
    assert all(quick == long for quick, long in pairs)
    assert "kin" in pairs[7][0][1] and "usage" in pairs[6][0][2]  # --help lists the commands; a usage error
    assert pairs[1][0][0].startswith("[('ascii', False)") and "'PROCESS'" in pairs[1][0][0]


async def test_the_prompts_parts_come_after_the_first_frame_or_with_the_first_question(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """A menu screen's first frame has the prompt without its question and input field (hidden
    at a menu); they are mounted a moment after it, or at once by a question (issue 25)."""
    from textual.widgets import Input, Label

    from valterm.ui.app import ValtermApp
    from valterm.ui.screens import base
    from valterm.ui.widgets.prompt import Prompt

    monkeypatch.setattr(base, "PROMPT_PARTS_AFTER", 3600.0)  # not within this test
    app = ValtermApp(tmp_path, "PROCESS")
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        prompt = app.screen.query_one(Prompt)
        assert not prompt.children and not app.screen.query(Input)
        await pilot.press("s")  # S: ARE YOU SURE YOU WANT TO EXIT (Y/N) ?
        await pilot.pause()
        assert [type(w) for w in prompt.children] == [Label, Input]
        assert prompt.question == "ARE YOU SURE YOU WANT TO EXIT (Y/N) ?:" and prompt.display
        await pilot.press("n")
        await pilot.pause()
        assert not prompt.display and "SESSION CONTINUES" in app.screen.messages.text
    monkeypatch.setattr(base, "PROMPT_PARTS_AFTER", 0.01)
    app = ValtermApp(tmp_path, "PROCESS")
    async with app.run_test(size=(160, 50)) as pilot:
        prompt = app.screen.query_one(Prompt)
        await until(pilot, lambda: bool(prompt.children), "the prompt's parts mounted by their timer")
        assert [type(w) for w in prompt.children] == [Label, Input]


async def test_the_prompts_parts_timer_does_nothing_on_a_screen_that_is_going(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """The timer that mounts the prompt's parts may run while its screen goes (the app ends):
    nothing is mounted then, and nothing fails."""
    from valterm.ui.app import ValtermApp
    from valterm.ui.screens import base
    from valterm.ui.widgets.prompt import Prompt

    monkeypatch.setattr(base, "PROMPT_PARTS_AFTER", 3600.0)  # the test calls it itself
    app = ValtermApp(tmp_path, "PROCESS")
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        prompt = app.screen.query_one(Prompt)
        monkeypatch.setattr(prompt, "_closing", True)
        prompt.mount_parts()
        assert not prompt.children
        monkeypatch.setattr(prompt, "_closing", False)
        prompt.mount_parts()
        assert len(prompt.children) == 2


async def test_the_prompts_parts_timer_does_nothing_on_a_prompt_already_gone(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """... nor once the prompt is detached, its screen gone (CI: MountError as the demo's
    hand-over test closed the app)."""
    from valterm.ui.app import ValtermApp
    from valterm.ui.screens import base
    from valterm.ui.widgets.prompt import Prompt

    monkeypatch.setattr(base, "PROMPT_PARTS_AFTER", 3600.0)
    app = ValtermApp(tmp_path, "PROCESS")
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.pause()
        gone = Prompt()  # detached, and no longer flagged as closing: as the app closed in CI
        assert not gone.is_attached and not gone._closing
        gone.mount_parts()
        assert not gone.children


def test_a_session_parses_the_robot_file_once() -> None:
    """The robot file gives the geometry, the drawn model and the timing: one parse of it a
    process (three at every start before, issue 25), and the same figures as a fresh parse."""
    probe = ("import json, sys, tempfile, tomllib\n"
             "parsed = []\n"
             "loads = tomllib.loads\n"
             "tomllib.loads = lambda text, **kw: parsed.append(text[:40]) or loads(text, **kw)\n"
             "from valterm.core import resources\n"
             "from valterm.core.session import Session\n"
             "s = Session(tempfile.mkdtemp(), setup='PROCESS')\n"
             "fresh = loads(resources.read_text('robot', 'PUMA.toml'))\n"
             "sim = s.simulator\n"
             "same = (list(sim.geometry.ready) == fresh['ready']['joints'] and sim.model.names == tuple(fresh['model']['names'])\n"
             "        and list(sim.timing.joint_speed) == fresh['timing']['joint_speed'])\n"
             "print(json.dumps([len(parsed), same]))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert json.loads(out.stdout.strip().splitlines()[-1]) == [1, True]


def test_a_sessions_setup_is_read_once_and_stamped_when_a_save_first_asks() -> None:
    """Issue 25 (the start): NAME.SET is read once, its stamp taken from the bytes parsed when
    first asked (a save), so hashlib (OpenSSL's library) is not loaded at the start; the stamp
    is the file's, and a save by another session since is still told."""
    probe = ("import sys, tempfile, subprocess\n"
             "ws = tempfile.mkdtemp()\n"
             "subprocess.run([sys.executable, '-c', f'from valterm.core.session import Session; Session({ws!r}, None)'], check=True)\n"
             "import builtins, io, os\n"
             "from valterm.core.session import Session\n"
             "from pathlib import Path\n"
             "opened = []\n"
             "real, real_os = io.open, os.open\n"
             "def counted(file, *a, **k):\n"
             "    if not isinstance(file, int):  # a descriptor: counted where os.open made it\n"
             "        opened.append(Path(file).name)\n"
             "    return real(file, *a, **k)\n"
             "def counted_os(file, *a, **k):\n"
             "    opened.append(Path(file).name)\n"
             "    return real_os(file, *a, **k)\n"
             "builtins.open = io.open = counted\n"
             "os.open = counted_os\n"
             "s = Session(ws, 'PROCESS')\n"
             "builtins.open = io.open = real\n"
             "os.open = real_os\n"
             "before = 'hashlib' in sys.modules\n"
             "from valterm.core.files.atomic import file_stamp\n"
             "same = s.setup_stamp == file_stamp(s.workspace.path('PROCESS', 'SET'))\n"
             "print(repr((opened.count('PROCESS.SET'), before, same, 'hashlib' in sys.modules)))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert ast.literal_eval(out.stdout.strip().splitlines()[-1]) == (1, False, True, True)


FIRST_FRAME_PROBE = """
import asyncio, json, sys, tempfile
from valterm.ui.app import ValtermApp
from valterm.testing import screen_rows

first = []

class Probe(ValtermApp):
    def _display(self, screen, renderable):
        if not first:
            first.append(["numpy" in sys.modules, self.session_read is not None,
                          "READING THE SET-UP FILE" in "\\n".join(screen_rows(self))])
        return super()._display(screen, renderable)

async def main():
    app = Probe(tempfile.mkdtemp(), "PROCESS")
    async with app.run_test(size=(160, 50)) as pilot:
        while app.session_read is None:
            await pilot.pause(0.02)
        await pilot.pause()
        rows = screen_rows(app)
        braille = any("\\u2801" <= ch <= "\\u28ff" for row in rows for ch in row)
        print(json.dumps([first[0], braille, "\\n".join(rows)]))

asyncio.run(main())
"""


def test_main_menu_is_drawn_before_the_setup_is_read_and_numpy_loads_then_its_picture() -> None:
    """``--setup``: MAIN MENU's first frame comes before the set-up is read, so without numpy
    and the core (issue 25, the start); the picture and the set-up's status come after it."""
    out = subprocess.run([sys.executable, "-c", FIRST_FRAME_PROBE], capture_output=True, text=True, check=True, timeout=240)
    (numpy_loaded, session_read, reading_said), braille, screen = json.loads(out.stdout.strip().splitlines()[-1])
    assert (numpy_loaded, session_read, reading_said) == (False, False, True)
    assert braille
    assert "MAIN MENU" in screen and "PROCESS.SET SAVED" in screen
    assert "SETUP FILE PROCESS.SET WITH 14 PARTS" in screen


async def test_keys_typed_before_the_setup_is_read_wait_for_it(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """A key typed at once (before the set-up is read after the first frame) is not lost and
    finds the session read: K opens KEYBOARD on PROCESS."""
    from valterm.ui.app import ValtermApp

    app = ValtermApp(tmp_path, "PROCESS")
    async with app.run_test(size=(80, 24)) as pilot:
        assert app.reading_setup  # nothing has read it yet: the first frame is still to come
        await pilot.press("k")
        await until(pilot, lambda: type(app.screen).__name__ == "KeyboardScreen", "KEYBOARD on PROCESS")
        assert type(app.screen).__name__ == "KeyboardScreen"
        assert app.session_read is not None and app.session_read.setup_name == "PROCESS"


async def test_the_session_is_read_when_first_asked_for_before_the_first_frame(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """Whatever asks for ``app.session`` before the set-up has been read gets it read then."""
    from valterm.ui.app import ValtermApp

    app = ValtermApp(tmp_path, "PROCESS")
    async with app.run_test(size=(80, 24)):
        assert app.session_read is None
        session = app.session
        assert session is not None and session.setup_name == "PROCESS"
        assert app.session_read is session and not app.reading_setup


async def test_a_setup_that_cannot_be_read_after_the_first_frame_shows_the_start_screen(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """A malformed --setup file is read after MAIN MENU's first frame: the start screen then
    says why, as it did when the set-up was read before."""
    from valterm.core.workspace import Workspace
    from valterm.ui.app import ValtermApp

    workspace = Workspace.open(tmp_path)
    (workspace.root / "BROKEN.SET").write_text("2\nMM\nnot a number\n")
    app = ValtermApp(tmp_path, "BROKEN")
    async with app.run_test(size=(80, 24)) as pilot:
        await until(pilot, lambda: type(app.screen).__name__ == "StartScreen", "the start screen")
        assert type(app.screen).__name__ == "StartScreen"
        await pilot.pause()
        from valterm.testing import screen_rows

        assert "BROKEN.SET" in "\n".join(screen_rows(app))
        assert app.session_read is None
