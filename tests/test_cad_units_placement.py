"""CAD units (MM/IN/M, glTF in metres), placement on a table, `import --into`, `valterm export`."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
import trimesh
from iges_writer import OURS, Sample, every_sample, of_kind

from valterm.core.cad.convert import import_cad
from valterm.core.cad.convert import native_units
from valterm.core.cad.placement import TOOL_DOWN_OAT, reachable, robot_at_ready
from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell
from valterm.core.collision.exact import collides
from valterm.core.files.setup import format_setup, parse_setup, read_setup, write_setup
from valterm.core.kinematics import Config, IKError, ik_oat
from valterm.core.resources import CELLS, bundled_files

def cell_file(name: str) -> Path:
    return next(p for p in bundled_files(CELLS) if p.name == f"{name}.SET")


def size(cell: WorkCell) -> np.ndarray:
    v = np.concatenate([p.vertices for p in cell.objects])
    return np.ptp(v, axis=0)


def cli(argv: list[str]) -> int:
    from valterm.cli import main
    return main(argv)


# --------------------------------------------------------------------------- units

def test_glb_is_read_in_metres(tmp_path):
    path = tmp_path / "box.glb"
    trimesh.creation.box(extents=(0.2, 0.1, 0.05)).export(path)
    assert native_units(path) == "M"
    # glTF's Y up is the world's Z up: (x, y, z) glTF -> (x, -z, y) world
    assert np.allclose(size(import_cad(path)), [200, 50, 100])
    # MM says the numbers are millimetres after all
    assert np.allclose(size(import_cad(path, units="MM", min_depth=0.01)), [0.2, 0.05, 0.1])


def test_stl_is_millimetres_unless_told_metres(tmp_path):
    path = tmp_path / "link.stl"
    trimesh.creation.box(extents=(0.3, 0.1, 0.1)).export(path)   # a robot link mesh in metres
    assert native_units(path) == "MM"
    assert np.allclose(size(import_cad(path, units="M")), [300, 100, 100])
    cell = import_cad(path, units="M")
    assert cell.units == "MM"   # a setup file holds MM or IN: metres are written as millimetres


@pytest.mark.parametrize("sample", every_sample(), ids=lambda s: s.id)
def test_iges_header_decides_the_units(sample: Sample):
    assert native_units(sample.path) == sample.units   # units flag 1: IN, 2: MM, 6: M


@of_kind("wireframe")
def test_iges_units_override(sample: Sample):
    chassis = sample.path
    inches = size(import_cad(chassis))
    assert np.allclose(size(import_cad(chassis, units="MM")) * 25.4, inches)
    assert np.allclose(size(import_cad(chassis, units="M")), size(import_cad(chassis, units="MM")) * 1000)


def test_cli_accepts_units_m(tmp_path, capsys):
    mesh = tmp_path / "link.stl"
    trimesh.creation.box(extents=(0.3, 0.1, 0.1)).export(mesh)
    assert cli(["--workspace", str(tmp_path / "ws"), "import", str(mesh), "--out", "LINK", "--units", "m"]) == 0
    assert "300.00 x 100.00 x 100.00 mm" in capsys.readouterr().out


# --------------------------------------------------------------------------- placement

def assert_placed_well(parts: list[Polyhedron], around: list[Polyhedron]) -> None:
    """Clear of the robot at READY, resting on (not in) the objects, and reachable from above."""
    robot = robot_at_ready()
    for part in parts:
        assert part.vertices[:, 0].min() > max(link.vertices[:, 0].max() for link in robot)  # not in the robot
        assert not any(collides(part, link) for link in robot)
        lifted = part.translated(np.array([0, 0, 0.01]))   # resting on a table top touches it
        assert not any(collides(lifted, obj) for obj in around)
    lo = np.min([p.vertices.min(axis=0) for p in parts], axis=0)
    hi = np.max([p.vertices.max(axis=0) for p in parts], axis=0)
    above = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2] + 50]
    solved = []
    for config in (Config(-1, 1, 1), Config(1, 1, 1), Config(-1, -1, 1), Config(1, -1, 1)):
        try:
            solved.append(ik_oat(above, TOOL_DOWN_OAT, config))
        except IKError:
            pass
    assert solved, f"no configuration reaches {above}"


@pytest.mark.parametrize("setup", ["PROCESS", "DEMO3", "CONV", None])
@of_kind("box")
def test_imported_part_lands_on_a_free_table_spot(setup, sample: Sample):
    around = read_setup(cell_file(setup)).objects if setup else []
    cell = import_cad(sample.path, around=around)
    assert not cell.warnings
    part = cell.objects[0]
    assert_placed_well([part], around)
    bottom = part.vertices[:, 2].min()
    if setup:   # it stands on the top of one of the setup's objects
        assert any(np.isclose(bottom, obj.vertices[:, 2].max()) for obj in around)
    else:       # the bundled cells' table height in front of the robot
        assert bottom == pytest.approx(-320.0)


@of_kind("box")
def test_second_import_lands_clear_of_the_first(sample: Sample):
    around = read_setup(cell_file("PROCESS")).objects
    first = import_cad(sample.path, around=around).objects
    second = import_cad(sample.path, around=around + first).objects
    assert_placed_well(second, around + first)
    assert not np.allclose(first[0].vertices, second[0].vertices)


@of_kind("wireframe")
def test_a_part_too_large_for_any_table_stands_in_front_with_a_warning(sample: Sample):
    cell = import_cad(sample.path)
    assert any("no free spot" in w for w in cell.warnings)
    robot = robot_at_ready()
    assert not any(collides(cell.objects[0], link) for link in robot)
    assert cell.objects[0].vertices[:, 0].min() > 0


def test_reachable_is_the_kinematics_answer():
    assert reachable([500, 0, -200]).tolist() == [True]
    assert reachable([[2000, 0, 0], [500, 100, -250], [0, 0, -2000]]).tolist() == [False, True, False]
    with pytest.raises(IKError):
        ik_oat([2000, 0, 0], TOOL_DOWN_OAT, Config(-1, 1, 1))


# --------------------------------------------------------------------------- setup files: names, numbers

def test_setup_writer_rounds_to_the_format_and_keeps_names(tmp_path):
    noisy = Polyhedron.box(np.array([17.141799999999996, 2.77e-05, -320.0]), np.array([67.1418, 30.0000001, -250.0]),
                           "CHASSIS B1")
    plain = Polyhedron.box(np.array([0.1 + 0.2, 0, 0]), np.array([50.0, 30, 70]), "PART 2")
    for units, decimals in (("MM", 2), ("IN", 4)):
        cell = WorkCell([noisy, plain], units=units)
        text = format_setup(cell)
        numbers = re.findall(r"\S+", "\n".join(line for line in text.splitlines()[3:] if not line.startswith(";")))
        fields = [f for n in numbers for f in n.split(",")]
        assert all(re.fullmatch(rf"-?\d+\.\d{{{decimals}}}", f) or f.isdigit() for f in fields), text
        assert "e-" not in text and "-0.00" not in text
        path = tmp_path / f"N{units}.SET"
        write_setup(path, cell)
        again = read_setup(path)
        assert [p.name for p in again.objects] == ["CHASSIS B1", "PART 2"]
        assert text.count("; NAME") == 1   # the default name is not written
        atol = 0.005 if units == "MM" else 0.00005 * 25.4
        for a, b in zip(cell.objects, again.objects):
            np.testing.assert_allclose(a.vertices, b.vertices, atol=atol + 1e-9, rtol=0)
        assert format_setup(again) == text   # round trip: byte for byte


def test_setup_reader_ignores_comment_lines():
    text = format_setup(WorkCell([Polyhedron.box(np.zeros(3), np.ones(3) * 10, "BLOCK")]))
    commented = "; written by hand\n" + text.replace("MM\n", "MM\n;another comment\n\n")
    cell = parse_setup(commented, "C.SET")
    assert cell.objects[0].name == "BLOCK" and len(cell.objects) == 1


# --------------------------------------------------------------------------- import --into

@of_kind("box")
def test_import_into_keeps_the_setup_and_appends_named_parts(tmp_path, capsys, sample: Sample):
    ws = tmp_path / "ws"
    name = sample.path.stem.upper()
    assert cli(["--workspace", str(ws), "import", str(sample.path), "--out", "BOX"]) == 0
    before = read_setup(ws / "PROCESS.SET")
    assert cli(["--workspace", str(ws), "import", str(sample.path), "--into", "process.set"]) == 0
    assert "1 part(s) added" in capsys.readouterr().out
    after = read_setup(ws / "PROCESS.SET")
    assert len(after.objects) == len(before.objects) + 1
    for a, b in zip(before.objects, after.objects):
        np.testing.assert_allclose(a.vertices, b.vertices, atol=0.005)
    assert after.objects[-1].name == name
    assert f"; NAME {name}" in (ws / "PROCESS.SET").read_text()
    assert_placed_well(after.objects[-1:], before.objects)
    # into one setup, out to another: the new file refuses to be overwritten without --force
    argv = ["--workspace", str(ws), "import", str(sample.path), "--into", "PROCESS", "--out", "BOX"]
    assert cli(argv) == 1
    assert "exists" in capsys.readouterr().err
    assert len(read_setup(ws / "BOX.SET").objects) == 1
    assert cli(argv + ["--force"]) == 0
    assert len(read_setup(ws / "BOX.SET").objects) == len(after.objects) + 1


def test_import_into_a_missing_setup_writes_nothing(tmp_path, capsys):
    ws = tmp_path / "ws"
    box = OURS["box"].path
    assert cli(["--workspace", str(ws), "import", str(box), "--into", "NOSUCH"]) == 1
    assert "no such setup file" in capsys.readouterr().err
    assert not (ws / "NOSUCH.SET").exists()
    # neither --out nor --into: a usage error
    assert cli(["--workspace", str(ws), "import", str(box)]) == 2
    assert "give --out NAME.SET" in capsys.readouterr().err


# --------------------------------------------------------------------------- valterm export

@of_kind("box")
def test_export_glb_is_metres_y_up_with_part_names(tmp_path, capsys, monkeypatch, sample: Sample):
    ws = tmp_path / "ws"
    name = sample.path.stem.upper()
    assert cli(["--workspace", str(ws), "import", str(sample.path), "--into", "PROCESS"]) == 0
    monkeypatch.chdir(tmp_path)  # a relative --out is relative to the current folder
    assert cli(["--workspace", str(ws), "export", "PROCESS.SET", "--out", "P.glb"]) == 0
    assert "metres, Y up" in capsys.readouterr().out
    assert not (ws / "P.glb").exists()
    scene = trimesh.load(tmp_path / "P.glb", force="scene")
    cell = read_setup(ws / "PROCESS.SET")
    assert name in scene.geometry and "RIGHT-HAND TABLE" in scene.geometry and "BASE" in scene.geometry
    box = cell.objects[-1].vertices
    mesh = scene.geometry[name].copy().apply_transform(scene.graph[name][0])
    # world (x, y, z) mm -> glTF (x, z, -y) m
    expected = np.stack([box[:, 0], box[:, 2], -box[:, 1]], 1) / 1000
    np.testing.assert_allclose(mesh.bounds, [expected.min(axis=0), expected.max(axis=0)], atol=1e-6)
    # the robot at READY stands up along +Y: its fingers about 1.04 m above the shoulder
    fingers = scene.geometry["FINGER"].copy().apply_transform(scene.graph["FINGER"][0])
    assert fingers.bounds[1][1] == pytest.approx(1.041, abs=0.01)
    assert scene.bounds[1][1] < 1.1 and scene.bounds[0][1] > -0.7   # nothing in millimetres


def test_export_obj_and_stl_keep_millimetres_and_say_so(tmp_path, capsys, monkeypatch):
    ws = tmp_path / "ws"
    (tmp_path / "here").mkdir()
    monkeypatch.chdir(tmp_path / "here")
    assert cli(["--workspace", str(ws), "export", "PROCESS", "--out", "P.OBJ", "--loc", "PROCESS", "--at", "A"]) == 0
    said = capsys.readouterr().out
    assert "millimetres, Z up" in said and "location A" in said
    text = (tmp_path / "here" / "P.OBJ").read_text()
    assert text.startswith("# valterm export: world millimetres, Z up")
    loaded = trimesh.load(tmp_path / "here" / "P.OBJ", force="scene", split_objects=True)
    assert "cell/RIGHT-HAND TABLE" in loaded.geometry
    out = tmp_path / "elsewhere" / "p.stl"
    assert cli(["--workspace", str(ws), "export", "PROCESS", "--out", str(out), "--pose", "0,-90,90,0,0,0"]) == 0
    stl = trimesh.load(out)
    assert stl.bounds[1][2] == pytest.approx(1041, abs=10)   # READY's fingers, in mm
    assert stl.bounds[0][2] == pytest.approx(-660, abs=1)    # the pedestal's foot


@pytest.mark.parametrize("argv, status, reason", [
    (["--pose", "1,2,3"], 2, "six joint angles"),
    (["--out", "P.step"], 2, "use FILE.glb, FILE.obj or FILE.stl"),
    (["--loc", "PROCESS"], 2, "go together"),
    (["--loc", "PROCESS", "--at", "NOWHERE"], 1, "no location NOWHERE"),
    (["--loc", "NOSUCH", "--at", "A"], 1, "no such location file"),
])
def test_export_errors(tmp_path, capsys, monkeypatch, argv, status, reason):
    ws = tmp_path / "ws"
    monkeypatch.chdir(tmp_path)
    out = [] if "--out" in argv else ["--out", "P.glb"]
    if status == 2:
        with pytest.raises(SystemExit) as caught:
            cli(["--workspace", str(ws), "export", "PROCESS", *out, *argv])
        assert caught.value.code == 2
    else:
        assert cli(["--workspace", str(ws), "export", "PROCESS", *out, *argv]) == 1
    assert reason in capsys.readouterr().err
    assert not list(ws.glob("P.*")) and not list(tmp_path.glob("P.*"))


def test_export_of_a_missing_setup_fails(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert cli(["--workspace", str(tmp_path / "ws"), "export", "NOSUCH.SET", "--out", "N.glb"]) == 1
    assert "no such setup file" in capsys.readouterr().err
