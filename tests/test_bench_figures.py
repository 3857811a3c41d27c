"""The app bench's arithmetic: frames are write bursts, and the rate counts drawing time only."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from valterm.bench.pty import BRAILLE, _read_until, cpu_seconds, drawing_figures, frame_figures
from valterm.bench.suite import GOALS, markdown


def test_bursts_are_frames_and_pauses_are_not_drawing_time() -> None:
    # three frames 20 ms apart (the second in two reads), a 1 s DELAY, two more 20 ms apart
    chunks = [(0.000, 100, True), (0.020, 60, True), (0.021, 40, False), (0.040, 100, True),
              (1.040, 300, False), (1.060, 100, True)]
    figures = frame_figures(chunks, "app_program", "160x50")
    assert figures["app_program_frames_160x50"] == 5
    assert figures["app_program_bytes_per_frame_160x50"] == pytest.approx(700 / 5)
    # four gaps: three of 20 ms drawing, the 1 s DELAY left out
    assert figures["app_program_fps_160x50"] == pytest.approx(3 / 0.060)


def test_robot_drawings_are_counted_per_second_of_motion() -> None:
    """At real pace: only bursts that write braille (the picture changed) are drawings, and
    the rate is per second of the program's motion (a DELAY or a transcript line is neither)."""
    picture = "⠁⣿ ⢀".encode()
    assert BRAILLE.search(picture) and not BRAILLE.search("PROCESS  6  APPRO A, -50 é".encode())
    chunks = [(0.000, 5000, True), (0.002, 3000, False),  # one drawing in two reads
              (0.030, 400, False),  # a transcript line alone
              (0.060, 6000, True), (2.000, 7000, True)]
    figures = drawing_figures(chunks, 0.5, "app_program", "160x50")
    assert figures["app_program_frames_160x50"] == 3
    assert figures["app_program_fps_160x50"] == pytest.approx(3 / 0.5)
    assert figures["app_program_bytes_per_frame_160x50"] == pytest.approx(21000 / 3)


@pytest.mark.skipif(not os.path.exists("/proc/self/stat"), reason="reads /proc")
def test_a_process_cpu_seconds_are_its_user_and_system_time() -> None:
    """The cores figure's CPU: this process's own, read from /proc as the bench reads the app's."""
    hertz = os.sysconf("SC_CLK_TCK")

    def ticks(times: os.times_result) -> int:  # whole clock ticks, so no float rounding decides
        return round(times.user * hertz) + round(times.system * hertz)

    with open("/dev/urandom", "rb") as noise:  # system time to see: the user time alone would not do
        while round(os.times().system * hertz) < 3:
            noise.read(1 << 22)
    before = os.times()
    seen = round(cpu_seconds(os.getpid()) * hertz)
    after = os.times()  # read after /proc: the worker's other threads use CPU in between too
    assert ticks(before) - 1 <= seen <= ticks(after) + 1


def test_the_cores_goal_is_shown_beside_the_bare_textual_peer() -> None:
    table = markdown({"machine": "test", "app_program_cores_160x50": 0.08,
                      "app_program_bare_cores_160x50": 0.05})
    assert "| `app_program_cores_160x50` | 0.08 | <= 0.1 | yes | the bare Textual app at the same frame rate, cores: 0.05 |" in table


def test_no_output_is_no_frame_rate() -> None:
    figures = frame_figures([], "app_move", "80x24")
    assert figures == {"app_move_fps_80x24": 0.0, "app_move_bytes_per_frame_80x24": 0.0,
                       "app_move_frames_80x24": 0.0}


def test_the_goals_table_says_what_was_not_measured() -> None:
    table = markdown({"machine": "test", "app_program_fps_160x50": 12.0})
    assert "| `app_program_fps_160x50` | 12.0 | >= 30 | **no** |" in table
    assert "| `app_move_fps_160x50` | not measured |" in table
    assert "app_program_bytes_per_frame_160x50" in GOALS


def _fake_run(monkeypatch: pytest.MonkeyPatch, met: bool) -> None:
    """``valterm bench`` on canned figures (the real run takes half a minute)."""
    import valterm.bench.suite as suite

    entries = {"machine": "test", "ik_single_us": 5.0 if met else 9.0, "collision_thesis_us_5parts": 30.0,
               "collision_thesis_us_300parts": 90.0,
               "goals": {"ik_single_us": {"goal": "<= 8", "met": met}}}
    monkeypatch.setattr(suite, "run_all", lambda app=True: entries)


@pytest.mark.parametrize("met, status", [(True, 0), (False, 1)])
def test_bench_exits_1_when_a_measured_goal_is_missed(monkeypatch: pytest.MonkeyPatch,
                                                      capsys: pytest.CaptureFixture[str],
                                                      met: bool, status: int) -> None:
    from valterm.cli import main

    _fake_run(monkeypatch, met)
    assert main(["bench", "--no-app"]) == status
    out, err = capsys.readouterr()
    assert "ik_single_us" in out
    assert ("1 goal(s) not met: ik_single_us" in err) == (not met)


def test_bench_svg_goes_through_the_safe_write_path(monkeypatch: pytest.MonkeyPatch, tmp_path,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    from valterm.cli import main

    _fake_run(monkeypatch, True)
    outside = tmp_path / "outside.svg"
    outside.write_text("keep")
    (tmp_path / "curve.svg").symlink_to(outside)
    assert main(["bench", "--no-app", "--svg", str(tmp_path / "curve.svg")]) == 1
    assert "curve.svg: is a symbolic link" in capsys.readouterr().err
    assert outside.read_text() == "keep"
    assert main(["bench", "--no-app", "--svg", str(tmp_path / "new.svg")]) == 0
    assert (tmp_path / "new.svg").read_text().startswith("<svg")


def test_the_start_counts_once_the_model_is_drawn_beside_main_menu() -> None:
    """The app's start time waits for the title and the model's braille (issue 25): a MAIN
    MENU drawn before its model would not count."""
    read, write = os.pipe()
    try:
        os.write(write, b"\x1b[1;1HMAIN MENU\x1b[2;1H   ")
        with pytest.raises(TimeoutError):
            _read_until(read, b"MAIN MENU", 0.2, picture=True)
        os.write(write, "MAIN MENU \u2800\u28ff".encode())  # a frame with the model
        seen, _ = _read_until(read, b"MAIN MENU", 5.0, picture=True)
        assert BRAILLE.search(seen)
        os.write(write, b"MAIN MENU")  # the bare app's one line: the title alone
        assert _read_until(read, b"MAIN MENU", 5.0)[0] == b"MAIN MENU"
    finally:
        os.close(read)
        os.close(write)


def test_the_start_row_shows_the_picture_beside_the_menu() -> None:
    """``app_start_vs_bare_x`` counts MAIN MENU's menu; the picture's ratio is printed on the
    same row so the two are read together (round 11), and has its own row and goal (issue
    40), beside the first start's, which has no picture kept."""
    table = markdown({"machine": "test", "app_start_vs_bare_x": 1.25, "app_start_bare_textual_s": 0.5,
                      "app_start_picture_vs_bare_x": 1.7, "app_start_picture_cold_vs_bare_x": 1.8})
    row = next(line for line in table.splitlines() if line.startswith("| `app_start_vs_bare_x`"))
    assert "| yes |" in row
    assert "a bare Textual app, s: 0.5" in row and "the model's picture beside the menu, x: 1.7" in row
    row = next(line for line in table.splitlines() if line.startswith("| `app_start_picture_vs_bare_x`"))
    assert "| <= 1.3 | **no** |" in row
    assert "a bare Textual app, s: 0.5" in row and "no picture kept), x (no goal): 1.8" in row


def test_the_grading_bench_grades_one_student_a_folder(tmp_path: Path) -> None:
    """The bench's class is what a class hands in, one folder a student, and every student
    passes: a layout `grade` reads as one student (as the flat folder became when students
    went by folder) is a failure, not a figure."""
    from valterm.bench.grading import _grade_seconds, write_class

    write_class(tmp_path, 3)
    assert sorted(p.name for p in (tmp_path / "class").iterdir()) == ["S000", "S001", "S002"]
    assert _grade_seconds(tmp_path, 2, 3) > 0
    (tmp_path / "class" / "S001" / "PROCESS.DAT").write_text("MOVE NOWHERE\n")
    with pytest.raises(RuntimeError, match="did not pass"):
        _grade_seconds(tmp_path, 1, 3)


def test_the_programs_motion_seconds_are_those_the_app_plays(tmp_path: Path) -> None:
    """The bench divides by the motions' seconds of PROCESS as the app plays it after
    D_DEFINE (the arm at the last location accepted, so READY is a motion of 2.1 s): the
    same Motion events' seconds, summed from the app's own stream."""
    import asyncio
    import math

    from valterm.bench.pty import program_motion_seconds
    from valterm.core.events import Motion
    from valterm.ui.app import ValtermApp

    async def played() -> float:
        app = ValtermApp(tmp_path, "PROCESS", motion_rate=math.inf)
        seconds: list[float] = []
        async with app.run_test(size=(160, 50)) as pilot:
            await pilot.pause()
            await pilot.press("v", "d", "d", *"PROCESS.LOC", "enter", *"aaaaa", "e")
            await pilot.pause()
            assert "LOCATIONS DEFINED: A, B, C, D, E, F" in "\n".join(app.screen.transcript)
            play = app.player.play

            def counted(events, post, stop=None):  # type: ignore[no-untyped-def]
                def through():  # type: ignore[no-untyped-def]
                    for event in events:
                        if isinstance(event, Motion):
                            seconds.append(float(event.seconds))
                        yield event
                play(through(), post, stop)

            app.player.play = counted  # type: ignore[method-assign]
            await pilot.press(*"EXECUTE PROCESS", "enter")
            for _ in range(200):
                if "COMPLETED" in "\n".join(app.screen.transcript):
                    break
                await pilot.pause(0.05)
        return sum(seconds)

    app_seconds = asyncio.run(played())
    assert app_seconds > 17.0  # READY from F (15.5 s from the set-up's pose)
    assert program_motion_seconds() == pytest.approx(app_seconds)


def test_the_capacity_figures_read_this_process_memory() -> None:
    """The serving guide's memory column: PSS and private dirty pages from smaps_rollup, in
    KiB, of a live process (this one): both there, and no more private than it is resident."""
    from valterm.bench.capacity import memory_kib

    if not os.path.exists(f"/proc/{os.getpid()}/smaps_rollup"):
        pytest.skip("no /proc/PID/smaps_rollup on this system")
    found = memory_kib(os.getpid())
    assert 1024 < found["private_kib"] <= found["pss_kib"] * 1.01


def test_the_import_s_peak_is_its_own_not_the_bench_process_s(tmp_path: Path) -> None:
    """The import's memory figure is the import process's peak: a bench process grown large
    (here 300 MB, touched) must not show in it. A child's ru_maxrss from wait4 counted the
    pages of the process it was forked from: 962 MB read for a 443 MB import."""
    import numpy as np

    from valterm.bench.cad import peak_of

    if not os.path.exists("/proc/self/status"):
        pytest.skip("no /proc/self/status on this system")
    ballast = np.ones(300 * 2**20 // 8)
    seconds, mb = peak_of(["--version"], tmp_path)
    assert ballast.sum() > 0 and seconds > 0
    assert 10 < mb < 150
