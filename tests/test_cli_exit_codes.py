"""The exit-status rule of every subcommand: 0 ok, 1 failure, 2 usage; messages on stderr
prefixed ``valterm:``; a bug becomes one line naming a log file with the traceback, exit 70;
a crash of the app exits non-zero the same way (issue 10 items 3-4, issue 16 item 4)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import valterm
from valterm.cli import COMMANDS, main
from valterm.commands import kin
from valterm.core.crashlog import EXIT_BUG
from valterm.core.workspace import WorkspaceError


def python(code: str, *argv: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True,
                          timeout=120, env={**os.environ, **(env or {})})


def messages(err: str) -> list[str]:
    """stderr without argparse's usage lines."""
    return [line for line in err.splitlines() if line and not line.startswith(("usage:", " "))]


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--version"]) == 0
    assert capsys.readouterr().out == f"valterm {valterm.version()}\n"
    assert valterm.version() == valterm.__version__  # the checkout's metadata agrees


def test_help_names_the_workspace_variable_and_the_exit_codes(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--help"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "$VALTERM_WORKSPACE" in out and "--version" in out
    assert "0 ok, 1 failure, 2 usage error, 70 internal error" in out
    assert main(["run", "--help"]) == 0
    assert "--workspace DIR" in capsys.readouterr().out


@pytest.mark.parametrize("argv", [
    ["bogus"], ["--bogus"], ["kin"], ["kin", "fk", "1", "2", "3"], ["kin", "ik", "1", "2", "3", "4", "5", "x"],
    ["kin", "ik", "1", "2", "3", "4", "5", "6", "--config", "SIDEWAYS"], ["cell"], ["cell", "show"],
    ["check"], ["run"], ["run", "PROCESS", "--loops", "many"], ["import", "X.IGS"], ["serve"],
    ["bench", "--bogus"], ["demo", "--bogus"], ["replay"], ["replay", "S.REC", "--speed", "fast"],
])
def test_usage_errors_exit_2_with_a_valterm_message(argv: list[str], tmp_path: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--workspace", str(tmp_path), *argv]) == 2
    captured = capsys.readouterr()
    said = messages(captured.err)
    assert said and all(line.startswith("valterm") for line in said), captured.err
    assert "Traceback" not in captured.err


@pytest.mark.parametrize("argv, message", [
    (["cell", "show", "NOSUCH"], "valterm: NOSUCH.SET: no such setup file"),
    (["cell", "show", "A-B"], "valterm: 'A-B' is not a valid name"),
    (["check", "NOSUCH"], "valterm: "),
    (["check", "/no/such/folder/X.DAT"], "valterm: /no/such/folder/X.DAT: no such program file"),
    (["run", "NOSUCH"], "valterm: NOSUCH.DAT: not in the workspace"),
    (["run", "PROCESS", "--cell", "NOSUCH"], "valterm: NOSUCH.SET: not in the workspace"),
    (["run", "PROCESS", "--loc", "../X.LOC"], "valterm: ../X.LOC: no such file"),
    (["kin", "ik", "3000", "0", "0", "0", "0", "0"], "valterm: kin ik: out of reach"),
])
def test_failures_exit_1_with_a_valterm_message(argv: list[str], message: str, tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--workspace", str(tmp_path), *argv]) == 1
    err = capsys.readouterr().err
    assert err.startswith(message), err
    assert all(line.startswith("valterm: ") for line in err.splitlines())


def test_check_of_a_bad_program_exits_1_and_of_a_bundled_one_0(tmp_path: Path,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "BAD.DAT"
    bad.write_text("    MOVE\n    GOTO 99\n")
    assert main(["check", str(bad)]) == 1
    assert main(["--workspace", str(tmp_path / "ws"), "check", "PROCESS"]) == 0
    assert "PROCESS:" in capsys.readouterr().out


def test_workspace_before_or_after_the_subcommand(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    after, before = tmp_path / "after", tmp_path / "before"
    assert main(["cell", "show", "PROCESS.SET", "--workspace", str(after)]) == 0
    assert (after / "PROCESS.SET").is_file()
    assert main(["--workspace", str(before), "run", "PROCESS", "--cell", "PROCESS", "--json"]) == 0
    assert (before / "PROCESS.DAT").is_file()
    # given twice, the one after the subcommand is the nearer and wins
    assert main(["--workspace", str(before), "check", "--workspace", str(after), "PROCESS"]) == 0
    capsys.readouterr()


def test_workspace_variable_is_used(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                    capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setenv("VALTERM_WORKSPACE", str(tmp_path / "env"))
    assert main(["cell", "show", "CONV"]) == 0
    assert (tmp_path / "env" / "CONV.SET").is_file()
    capsys.readouterr()


def test_a_refusal_escaping_a_command_is_one_message_exit_1(monkeypatch: pytest.MonkeyPatch,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    def refuse(*args: object, **kwargs: object) -> None:
        raise WorkspaceError("EVIL3.DAT links outside the workspace; refusing to use it")

    monkeypatch.setattr(kin, "_fk_pose", refuse)
    assert main(["kin", "fk", "0", "0", "0", "0", "0", "0"]) == 1
    assert capsys.readouterr().err == "valterm: EVIL3.DAT links outside the workspace; refusing to use it\n"


def test_a_bug_is_one_line_naming_a_log_with_the_traceback(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    def bug(*args: object, **kwargs: object) -> None:
        return {}["no such key"]  # type: ignore[return-value]

    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    monkeypatch.setattr(kin, "_fk_pose", bug)
    assert main(["kin", "fk", "0", "0", "0", "0", "0", "0"]) == EXIT_BUG == 70
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1
    logs = list((tmp_path / "state" / "valterm").glob("crash-*.log"))
    assert len(logs) == 1
    assert err == f"valterm: internal error (KeyError: 'no such key'); the traceback is in {logs[0]}\n"
    log = logs[0].read_text()
    assert "Traceback (most recent call last)" in log and "in bug" in log and "KeyError" in log
    assert log.startswith(f"valterm {valterm.version()} on Python")


def test_a_log_folder_that_cannot_be_written_falls_back_to_the_temporary_folder(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("XDG_STATE_HOME", str(blocker))
    monkeypatch.setenv("TMPDIR", str(tmp_path / "tmp"))
    (tmp_path / "tmp").mkdir()
    import tempfile
    monkeypatch.setattr(tempfile, "tempdir", None)  # re-read TMPDIR
    monkeypatch.setattr(kin, "_fk_pose", lambda *a, **k: 1 / 0)
    assert main(["kin", "fk", "0", "0", "0", "0", "0", "0"]) == 70
    err = capsys.readouterr().err
    assert f"the traceback is in {tmp_path / 'tmp' / 'valterm'}" in err


BROKEN_BENCH = "import sys; sys.modules['valterm.commands.bench'] = None; from valterm.cli import main; " \
               "sys.exit(main(sys.argv[1:]))"


@pytest.mark.parametrize("argv", [["bench", "--help"], ["--help"]])
def test_an_import_error_in_a_command_module_surfaces(argv: list[str], tmp_path: Path) -> None:
    """A command's module loads when the command line names it (or --help lists them all):
    an import error there is a bug, exit 70 with the one line naming it."""
    result = python(BROKEN_BENCH, *argv, env={"XDG_STATE_HOME": str(tmp_path)})
    assert result.returncode == EXIT_BUG
    assert "ModuleNotFoundError: import of valterm.commands.bench halted" in result.stderr


def test_a_command_line_loads_only_its_own_commands_module(tmp_path: Path) -> None:
    """The app and every other command do without a broken module they do not use (issue 25:
    the app's start loads no command's module)."""
    result = python(BROKEN_BENCH, "kin", "fk", "0", "0", "0", "0", "0", "0", env={"XDG_STATE_HOME": str(tmp_path)})
    assert (result.returncode, result.stderr) == (0, "")
    assert "431.80" in result.stdout
    probe = ("import sys; from valterm.cli import chosen_commands; "
             "print(chosen_commands(['--setup', 'run', '--robot', 'PUMA']), chosen_commands(['--workspace', 'W', 'run', 'X']), "
             "chosen_commands(['-h', 'run']), chosen_commands(['--rules', 'bad']) == chosen_commands(['--help']), "
             "'valterm.commands.run' in sys.modules)")
    assert python(probe).stdout.strip() == f"() ('run',) {COMMANDS} True False"


def test_a_closed_pipe_ends_quietly(tmp_path: Path) -> None:
    poses = tmp_path / "poses.txt"
    poses.write_text("".join(f"{i % 90} -90 90 0 0 0\n" for i in range(20000)))
    with poses.open() as stdin:
        process = subprocess.Popen([sys.executable, "-m", "valterm", "kin", "fk", "--json"], stdin=stdin,
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert process.stdout is not None and process.stderr is not None
    assert process.stdout.readline().startswith('{"xyz"')
    process.stdout.close()  # the reader goes away, like `| head -1`
    assert process.wait(timeout=120) == 0
    assert process.stderr.read() == ""


FORCED_APP_CRASH = """
import sys
from valterm.ui import app as ui_app
from valterm.ui.screens.start import StartScreen

def broken(self):
    raise RuntimeError("forced crash in a screen")

StartScreen.on_mount = broken
real_run = ui_app.ValtermApp.run
ui_app.ValtermApp.run = lambda self, **kw: real_run(self, headless=True, size=(80, 24))
from valterm.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_a_crash_of_the_app_exits_non_zero_with_one_line_and_the_log(tmp_path: Path) -> None:
    result = python(FORCED_APP_CRASH, "--workspace", str(tmp_path / "ws"),
                    env={"XDG_STATE_HOME": str(tmp_path / "state")})
    assert result.returncode == EXIT_BUG, result.stderr
    logs = list((tmp_path / "state" / "valterm").glob("crash-*.log"))
    assert len(logs) == 1
    assert result.stderr.strip().splitlines() == [
        f"valterm: internal error (RuntimeError: forced crash in a screen); the traceback is in {logs[0]}"]
    log = logs[0].read_text()
    assert "in broken" in log and "RuntimeError: forced crash in a screen" in log


def test_a_bug_while_building_the_parser_is_caught_too(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    def broken(sub: object) -> None:
        raise AttributeError("'NoneType' object has no attribute 'add_parser'")

    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    monkeypatch.setattr(kin, "register", broken)
    assert main(["--version"]) == 70
    err = capsys.readouterr().err
    assert err.startswith("valterm: internal error (AttributeError: ") and len(err.splitlines()) == 1
