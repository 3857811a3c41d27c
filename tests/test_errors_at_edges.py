"""The edges catch the project's own errors, never a bare built-in one: a refusal of what
the user gave is a ``RefusedValue`` (a ValtermError) and gets its message; a ValueError
from anywhere else is a bug and exits 70 with its traceback logged."""

from __future__ import annotations

from pathlib import Path

import pytest

from valterm.cli import main
from valterm.core.errors import RefusedValue, ValtermError
from valterm.core.kinematics import Config
from valterm.core.val.dialects import check_dialect


def test_refused_values_are_the_project_s_errors() -> None:
    from valterm.commands.export import _pose
    from valterm.commands.render import parse_size
    from valterm.commands.serve import public_url_of

    for refuse in (lambda: parse_size("80by24"), lambda: parse_size("2x2"), lambda: Config.parse("SIDEWAYS"),
                   lambda: Config.parse("LEFTY RIGHTY"), lambda: check_dialect("cobol"),
                   lambda: _pose("1,2,3"), lambda: public_url_of("ftp://x")):
        with pytest.raises(RefusedValue) as caught:
            refuse()
        assert isinstance(caught.value, ValtermError) and str(caught.value)


@pytest.mark.parametrize(("argv", "status", "said"), [
    (["render", "--size", "80by24"], 2, "valterm: --size '80by24': give WIDTHxHEIGHT, e.g. 80x24"),
    (["render", "--at", "A"], 2, "valterm: --at NAME needs --loc FILE"),
    (["kin", "ik", "--config", "SIDEWAYS", "0", "0", "0", "0", "0", "0"], 2, "valterm: kin ik: --config: 'SIDEWAYS'"),
    (["export", "PROCESS.SET", "--out", "x.glb", "--pose", "1,2"], 2, "--pose needs six joint angles"),
])
def test_a_refusal_is_said_with_its_usage_status(argv: list[str], status: int, said: str, tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    try:
        got = main(["--workspace", str(tmp_path / "ws"), *argv])
    except SystemExit as done:  # argparse's own usage error (export) exits there
        got = int(done.code or 0)
    assert got == status
    assert said in capsys.readouterr().err


@pytest.mark.parametrize(("target", "argv"), [
    ("valterm.core.render.views.preset_angles", ["render"]),
    ("valterm.core.kinematics.Config.parse", ["kin", "ik", "0", "0", "0", "0", "0", "0"]),
])
def test_a_bare_value_error_is_a_bug_not_a_message(target: str, argv: list[str], tmp_path: Path,
                                                   monkeypatch: pytest.MonkeyPatch,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    def bug(*args: object, **kwargs: object) -> None:
        raise ValueError("a bug inside")

    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    monkeypatch.setattr(target, bug)
    assert main(["--workspace", str(tmp_path / "ws"), *argv]) == 70
    err = capsys.readouterr().err
    assert "internal error (ValueError: a bug inside)" in err
    (log,) = (tmp_path / "state" / "valterm").glob("crash-*.log")
    assert "Traceback" in log.read_text()


def test_a_bare_key_error_in_a_step_is_a_bug_and_an_undeclared_variable_a_message() -> None:
    from valterm.core.events import Error
    from valterm.core.simulator import Simulator
    from valterm.core.val.interpreter import Interpreter, program_from_lines

    sim = Simulator(None)
    program = program_from_lines("P", ["    X = Y + 1", "    MOVE A"])
    interpreter = Interpreter(sim, lambda name: program, {})
    events = list(interpreter.execute("P"))
    said = [e.message for e in events if isinstance(e, Error)]
    assert said == ["VARIABLE Y IS NOT DECLARED", "LOCATION A IS NOT DEFINED"]

    def broken(*args: object, **kwargs: object) -> None:
        raise KeyError("a bug inside the simulator")

    sim.locations["A"] = sim.here_location()
    sim.move = broken  # type: ignore[method-assign]
    with pytest.raises(KeyError, match="a bug inside"):
        list(interpreter.execute("P"))
