"""Generate (main menu G): GLB/OBJ/STL export round trip; and the `valterm import` command."""

from __future__ import annotations

import argparse

import numpy as np
import pytest
import trimesh
from iges_writer import Sample, of_kind

from valterm.core.cad.convert import import_cad
from valterm.core.cad.export import export_scene, polyhedron_mesh
from valterm.core.cell.polyhedron import Polyhedron
from valterm.core.cell.workcell import WorkCell

def scene_cell() -> tuple[WorkCell, list[Polyhedron]]:
    parts = [Polyhedron.box(np.array([400.0, -50, -320]), np.array([450.0, -20, -250])),
             Polyhedron.box(np.array([-460.0, 500, -320]), np.array([40.0, 1100, -280]))]
    # a hexagonal prism: not a box, k = 6
    ang = np.linspace(0, 2 * np.pi, 6, endpoint=False)
    hexa = np.stack([100 + 30 * np.cos(ang), 200 + 30 * np.sin(ang), np.zeros(6)], 1)
    parts.append(Polyhedron.from_polygons(hexa, hexa + [0, 0, 80]))
    robot = [Polyhedron.box(np.array([-80.0, -80, -700]), np.array([80.0, 80, 0]), "BASE"),
             Polyhedron.box(np.array([-40.0, -40, 0]), np.array([40.0, 300, 60]), "UPPERARM")]
    return WorkCell(parts, name="TEST"), robot


def test_polyhedron_mesh_is_closed_and_outward():
    cell, robot = scene_cell()
    for poly in cell.objects + robot:
        mesh = polyhedron_mesh(poly)
        assert mesh.is_watertight
        assert mesh.volume > 0  # outward winding
        assert np.allclose(mesh.bounds, [poly.vertices.min(axis=0), poly.vertices.max(axis=0)])


def test_obj_round_trip_in_millimetres(tmp_path):
    cell, robot = scene_cell()
    path = export_scene(cell, robot, tmp_path / "scene.obj")
    assert path.read_text().startswith("# valterm export: world millimetres, Z up")
    loaded = trimesh.load(path, force="scene", split_objects=True)
    assert len(loaded.geometry) == len(cell.objects) + len(robot)
    all_v = np.concatenate([p.vertices for p in cell.objects + robot])
    assert np.allclose(loaded.bounds, [all_v.min(axis=0), all_v.max(axis=0)], atol=1e-5)
    names = set(loaded.geometry)
    assert {"robot/BASE", "robot/UPPERARM", "cell/PART 1", "cell/PART 2", "cell/PART 3"} == names
    for poly, name in zip(robot, ("robot/BASE", "robot/UPPERARM")):
        mesh = loaded.geometry[name]
        assert np.allclose(mesh.bounds, [poly.vertices.min(axis=0), poly.vertices.max(axis=0)], atol=1e-5)


def test_glb_round_trip_in_metres_y_up(tmp_path):
    cell, robot = scene_cell()
    path = export_scene(cell, robot, tmp_path / "scene.glb")
    loaded = trimesh.load(path, force="scene")
    assert set(loaded.geometry) == {"BASE", "UPPERARM", "PART 1", "PART 2", "PART 3"}
    for poly, name in zip(robot + cell.objects, ("BASE", "UPPERARM", "PART 1", "PART 2", "PART 3")):
        mesh = loaded.geometry[name].copy().apply_transform(loaded.graph[name][0])
        v = poly.vertices / 1000.0
        gltf = np.stack([v[:, 0], v[:, 2], -v[:, 1]], 1)   # Z up -> Y up
        assert np.allclose(mesh.bounds, [gltf.min(axis=0), gltf.max(axis=0)], atol=1e-7)


def test_stl_is_one_mesh_in_millimetres(tmp_path):
    cell, robot = scene_cell()
    mesh = trimesh.load(export_scene(cell, robot, tmp_path / "scene.stl"))
    all_v = np.concatenate([p.vertices for p in cell.objects + robot])
    assert np.allclose(mesh.bounds, [all_v.min(axis=0), all_v.max(axis=0)], atol=1e-3)


def test_glb_groups_robot_and_cell_nodes(tmp_path):
    cell, robot = scene_cell()
    path = export_scene(cell, robot, tmp_path / "scene.glb")
    loaded = trimesh.load(path, force="scene")
    assert "robot" in loaded.graph.nodes and "cell" in loaded.graph.nodes
    assert loaded.graph.transforms.parents["BASE"] == "robot"
    assert loaded.graph.transforms.parents["PART 1"] == "cell"


def test_export_reimports(tmp_path):
    cell, robot = scene_cell()
    path = export_scene(cell, [], tmp_path / "cell.obj")
    again = import_cad(path)
    assert len(again.objects) == 3
    sizes = sorted(tuple(np.round(np.ptp(p.vertices, axis=0), 6)) for p in again.objects)
    expected = sorted(tuple(np.round(np.ptp(p.vertices, axis=0), 6)) for p in cell.objects)
    assert np.allclose(sizes, expected)


def test_export_refuses_other_formats(tmp_path):
    cell, robot = scene_cell()
    with pytest.raises(ValueError, match=r"\.glb, \.obj or \.stl"):
        export_scene(cell, robot, tmp_path / "scene.step")
    with pytest.raises(ValueError, match="nothing to export"):
        export_scene(WorkCell([]), [], tmp_path / "empty.obj")


# --------------------------------------------------------------------------- valterm import

def run(argv: list[str]) -> int:
    from valterm.commands import cad
    parser = argparse.ArgumentParser()
    parser.add_argument("--workspace")
    cad.register(parser.add_subparsers(dest="command"))
    args = parser.parse_args(argv)
    return args.func(args)


@pytest.fixture
def setup_module_ready():
    pytest.importorskip("valterm.core.files.setup")
    pytest.importorskip("valterm.core.workspace")


@of_kind("box")
def test_import_command_writes_a_setup_file(tmp_path, capsys, setup_module_ready, sample: Sample):
    box = sample.path
    side = sample.size_mm[0]
    ws = tmp_path / "ws"
    assert run(["--workspace", str(ws), "import", str(box), "--out", "box.set"]) == 0
    out = capsys.readouterr().out
    assert "BOX.SET written" in out and f"{side:.2f} x {side:.2f} x {side:.2f} mm" in out
    from valterm.core.files.setup import read_setup
    cell = read_setup(ws / "BOX.SET")
    assert len(cell.objects) == 1
    assert np.allclose(np.ptp(cell.objects[0].vertices, axis=0), side)
    # no silent overwrite
    assert run(["--workspace", str(ws), "import", str(box), "--out", "BOX.SET"]) == 1
    assert "exists" in capsys.readouterr().err
    assert run(["--workspace", str(ws), "import", str(box), "--out", "BOX", "--force", "--system", "s"]) == 0


@of_kind("wireframe")
def test_import_command_inches(tmp_path, capsys, setup_module_ready, sample: Sample):
    chassis = sample.path
    ws = tmp_path / "ws"
    assert run(["--workspace", str(ws), "import", str(chassis), "--out", "CHASSIS"]) == 0
    text = (ws / "CHASSIS.SET").read_text().splitlines()
    assert text[0].strip() == "1" and text[1].strip() == "IN" and text[2].strip() == "W"
    from valterm.core.files.setup import read_setup
    cell = read_setup(ws / "CHASSIS.SET")
    assert np.ptp(cell.objects[0].vertices, axis=0)[0] == pytest.approx(sample.size_mm[0], abs=0.01)


def test_import_command_errors(tmp_path, capsys, setup_module_ready):
    ws = tmp_path / "ws"
    bad = tmp_path / "bad.igs"
    bad.write_text("short line\n")
    assert run(["--workspace", str(ws), "import", str(bad), "--out", "BAD"]) == 1
    assert capsys.readouterr().err.startswith(f"valterm: {bad}:1: line is 10 columns long")
    good = tmp_path / "b.stl"
    trimesh.creation.box(extents=(1, 1, 1)).export(good)
    assert run(["--workspace", str(ws), "import", str(good), "--out", "TOO_LONG_NAME.SET"]) == 1
    assert "not a valid name" in capsys.readouterr().err
    assert run(["--workspace", str(ws), "import", str(tmp_path / "missing.igs"), "--out", "X"]) == 1
    assert "no such file" in capsys.readouterr().err
    assert not (ws / "BAD.SET").exists()
