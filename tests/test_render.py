"""`valterm render`: the model view's picture without the app (issue 12)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import pytest

from valterm.cli import main
from valterm.commands.render import draw
from valterm.core.render.legend import TRACE_COLOUR
from valterm.core.render.overlays import Trace, cell_points, clamp_point
from valterm.core.render.raster import ViewTransform
from valterm.core.render.views import (
    angles,
    make_view,
    next_preset,
    orbit,
    preset_angles,
)
from valterm.core.session import Session


@pytest.fixture
def ws(tmp_path: Path) -> str:
    return str(tmp_path / "ws")


def render(ws: str, capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    code = main(["--workspace", ws, "render", *args])
    out, err = capsys.readouterr()
    return code, out, err


def lit(lines: list[str]) -> int:
    """Braille dots lit in the picture."""
    return sum((ord(c) - 0x2800).bit_count() for line in lines for c in line if "\u2800" < c <= "\u28ff")


@pytest.mark.parametrize("size", [(80, 24), (160, 50)])
def test_the_default_render_fits_the_size_and_shows_robot_and_cell(ws, capsys, size) -> None:
    w, h = size
    code, out, err = render(ws, capsys, "--setup", "PROCESS", "--size", f"{w}x{h}")
    assert code == 0 and err == ""
    lines = out.rstrip("\n").split("\n")
    assert len(lines) == h and all(len(line) == w for line in lines)
    assert lit(lines) > 40 * w // 80  # robot and cell, not an empty frame
    assert {"X", "Y", "Z"} <= set("".join(lines))  # the WORLD axes are labelled


def test_json_gives_the_view_and_the_lines(ws, capsys) -> None:
    code, out, _ = render(ws, capsys, "--json", "--size", "60x20")
    result = json.loads(out)
    az, el = preset_angles("iso")
    assert result["view"] == {"azimuth": az, "elevation": el}
    assert 0 < el < 90 and az % 90 != 0  # oblique: away from the axes
    assert len(result["lines"]) == 20 and all(len(line) == 60 for line in result["lines"])
    code, out, _ = render(ws, capsys, "--json", "--azimuth", "30", "--elevation", "10")
    assert code == 0 and json.loads(out)["view"] == {"azimuth": 30.0, "elevation": 10.0}


def test_side_is_the_thesis_view(ws, capsys) -> None:
    # the thesis's view is the bare SCS mapping: X_s = Y_w, Y_s = Z_w, looking along X_w
    view = make_view(np.array([[0.0, 0, 0], [1, 1, 1]]), *preset_angles("side"))
    assert np.allclose(view.rotation, np.eye(3))
    assert np.allclose(view.rotation, ViewTransform().rotation)
    _code, out, _ = render(ws, capsys, "--view", "side", "--json")
    assert json.loads(out)["view"] == {"azimuth": 0.0, "elevation": 0.0}
    side = json.loads(out)["lines"]
    _, out, _ = render(ws, capsys, "--json")
    assert side != json.loads(out)["lines"]


def test_trace_adds_the_clamps_path(ws, capsys) -> None:
    session = Session(ws)
    plain = draw(session.simulator, *preset_angles("iso"), (80, 24))["frame"]
    assert not (plain.colours == TRACE_COLOUR).any()
    code, out, err = render(ws, capsys, "--trace", "PROCESS.DAT", "--loc", "PROCESS.LOC", "--json")
    assert code == 0, err
    traced_lines = json.loads(out)["lines"]
    _, out, _ = render(ws, capsys, "--json")
    assert lit(traced_lines) > lit(json.loads(out)["lines"])
    # the same picture built in-process: the trace colour is there
    args = argparse.Namespace(trace="PROCESS.DAT", joints=None, at=None)
    from valterm.commands.render import _place

    session = Session(ws)
    session.load_locations("PROCESS")
    trace = _place(session, args)
    assert len(trace) > 20
    frame = draw(session.simulator, *preset_angles("iso"), (80, 24), trace=trace)["frame"]
    assert (frame.colours == TRACE_COLOUR).sum() > 10


def test_at_places_the_robot_and_svg_is_written(ws, capsys, tmp_path) -> None:
    svg = tmp_path / "cell.svg"
    code, _out, err = render(ws, capsys, "--loc", "PROCESS.LOC", "--at", "A", "--svg", str(svg))
    assert code == 0, err
    text = svg.read_text()
    assert text.startswith("<svg") and text.count("<line") > 100


@pytest.mark.parametrize("args, status, words", [
    (["--size", "3x3"], 2, "--size"),
    (["--size", "wide"], 2, "--size"),
    (["--view", "diagonal"], 2, "diagonal"),
    (["--view", "side", "--azimuth", "3"], 2, "not both"),
    (["--elevation", "120"], 2, "elevation"),
    (["--at", "A"], 2, "--loc"),
    (["--setup", "NOPE"], 2, "NOPE.SET"),
    (["--trace", "NOPE.DAT"], 2, "NOPE.DAT"),
    (["--joints", "0", "0", "0", "0", "0", "900"], 2, "joint 6"),
    (["--loc", "PROCESS.LOC", "--at", "NOWHERE"], 1, "NOWHERE"),
])
def test_bad_input_is_a_located_message(ws, capsys, args, status, words) -> None:
    code, out, err = render(ws, capsys, *args)
    assert code == status and out == ""
    assert err.startswith("valterm: ") and words in err and "Traceback" not in err


def test_orbit_and_presets_keep_the_angles() -> None:
    view = make_view(np.array([[0.0, 0, 0], [1, 1, 1]]), -40.0, 30.0)
    assert angles(view) == pytest.approx((-40.0, 30.0))
    orbit(view, 15, -10)
    assert angles(view) == pytest.approx((-25.0, 20.0))
    orbit(view, 0, 200)  # clamped at the zenith
    assert angles(view)[1] == pytest.approx(90.0)
    names = []
    view = make_view(np.zeros((1, 3)), *preset_angles("iso"))
    for _ in range(4):
        name = next_preset(view)
        names.append(name)
        from valterm.core.render.views import orient

        orient(view, *preset_angles(name))
    assert names == ["side", "front", "top", "iso"]


def test_the_clamp_point_follows_the_robot() -> None:
    session = Session(None)
    sim = session.simulator
    start = clamp_point(sim)
    trace = Trace([start])
    sim.stand_at([30.0, -90.0, 90.0, 0.0, 0.0, 0.0])
    trace.add(clamp_point(sim))
    trace.add(clamp_point(sim))  # no move: no point
    assert len(trace) == 2 and trace.segments().shape == (1, 2, 3)
    assert len(cell_points(sim, trace)) > len(sim.cell.objects) * 8


def test_ascii_render_is_plain_ascii_and_the_app_options_count(ws, capsys) -> None:
    code = main(["--workspace", ws, "--ascii", "--setup", "CONV", "render", "--size", "60x20"])
    out = capsys.readouterr().out
    lines = out.rstrip("\n").split("\n")
    assert code == 0 and len(lines) == 20 and all(len(line) == 60 for line in lines)
    assert out.isascii() and sum(c not in " \n" for c in out) > 50
    code, conv, _ = render(ws, capsys, "--setup", "CONV", "--ascii", "--size", "60x20")
    assert conv == out
    _, process, _ = render(ws, capsys, "--ascii", "--size", "60x20")
    assert process != out  # a different cell
