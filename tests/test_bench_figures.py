"""The app bench's arithmetic: frames are write bursts, and the rate counts drawing time only."""

from __future__ import annotations

import pytest

from valterm.bench.pty import frame_figures
from valterm.bench.suite import GOALS, markdown


def test_bursts_are_frames_and_pauses_are_not_drawing_time() -> None:
    # three frames 20 ms apart (the second in two reads), a 1 s DELAY, two more 20 ms apart
    chunks = [(0.000, 100), (0.020, 60), (0.021, 40), (0.040, 100),
              (1.040, 300), (1.060, 100)]
    figures = frame_figures(chunks, "app_program", "160x50")
    assert figures["app_program_frames_160x50"] == 5
    assert figures["app_program_bytes_per_frame_160x50"] == pytest.approx(700 / 5)
    # four gaps: three of 20 ms drawing, the 1 s DELAY left out
    assert figures["app_program_fps_160x50"] == pytest.approx(3 / 0.060)


def test_no_output_is_no_frame_rate() -> None:
    figures = frame_figures([], "app_move", "80x24")
    assert figures == {"app_move_fps_80x24": 0.0, "app_move_bytes_per_frame_80x24": 0.0,
                       "app_move_frames_80x24": 0.0}


def test_the_goals_table_says_what_was_not_measured() -> None:
    table = markdown({"machine": "test", "app_program_fps_160x50": 12.0})
    assert "| `app_program_fps_160x50` | 12.0 | >= 30 | **no** |" in table
    assert "| `app_move_fps_160x50` | not measured |" in table
    assert "app_program_bytes_per_frame_160x50" in GOALS
