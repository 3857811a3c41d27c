"""Mesh import (start-up choice U): STL/OBJ/PLY/GLB written by trimesh, and bad input."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from valterm.core.cad.convert import import_cad
from valterm.core.cad.errors import CadImportError
from valterm.core.cad.mesh import read_mesh_parts


def extents(cell) -> np.ndarray:
    lo = np.min([p.vertices.min(axis=0) for p in cell.objects], axis=0)
    hi = np.max([p.vertices.max(axis=0) for p in cell.objects], axis=0)
    return hi - lo


def box(size, at=(0, 0, 0)) -> trimesh.Trimesh:
    mesh = trimesh.creation.box(extents=size)
    mesh.apply_translation(at)
    return mesh


@pytest.mark.parametrize("ext", ["stl", "obj", "ply", "glb", "off"])
def test_single_box_every_format(tmp_path, ext):
    path = tmp_path / f"block.{ext}"
    box((40, 30, 20), at=(7, 8, 9)).export(path)
    # a glTF is in metres by its specification; MM says these numbers are millimetres
    cell = import_cad(path, units="MM" if ext == "glb" else None, place_at=(0, 0, 0))
    assert len(cell.objects) == 1
    # a glTF's Y up is the world's Z up
    assert np.allclose(extents(cell), [40, 20, 30] if ext == "glb" else [40, 30, 20])
    assert np.allclose(cell.objects[0].vertices.min(axis=0), 0)
    assert cell.units == "MM" and cell.name == "BLOCK"


def test_units_in_scales_by_25_4(tmp_path):
    path = tmp_path / "b.stl"
    box((1, 2, 3)).export(path)
    cell = import_cad(path, units="IN")
    assert np.allclose(extents(cell), [25.4, 50.8, 76.2]) and cell.units == "IN"


def test_cylinder_outline_is_capped_and_encloses(tmp_path):
    path = tmp_path / "cyl.stl"
    trimesh.creation.cylinder(radius=50, height=10, sections=128).export(path)
    cell = import_cad(path)
    poly = cell.objects[0]
    assert 4 <= poly.k <= 32
    assert np.allclose(extents(cell), [100, 100, 10], atol=1e-6)   # thin axis = the cylinder axis


def test_scene_with_several_meshes_gives_several_parts(tmp_path):
    scene = trimesh.Scene()
    scene.add_geometry(box((10, 10, 10)), node_name="a", geom_name="a")
    # the same geometry placed twice by the scene graph: two parts
    scene.add_geometry(box((20, 10, 5)), node_name="b", geom_name="b",
                       transform=trimesh.transformations.translation_matrix([100, 0, 0]))
    path = tmp_path / "two.glb"
    scene.export(path)
    parts = read_mesh_parts(path)
    assert sorted(p.name for p in parts) == ["a", "b"]
    cell = import_cad(path, units="MM")
    assert len(cell.objects) == 2
    assert np.allclose(extents(cell), [115, 10, 10])
    assert len(import_cad(path, parts=1).objects) == 1
    with pytest.raises(CadImportError, match="holds 2 meshes"):
        import_cad(path, parts=3)


def test_obj_objects_are_parts(tmp_path):
    path = tmp_path / "pair.obj"
    path.write_text(
        "o first\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n"
        "o second\nv 10 0 0\nv 12 0 0\nv 10 2 0\nv 10 0 2\nf 5 6 7\nf 5 6 8\nf 5 7 8\nf 6 7 8\n")
    cell = import_cad(path)
    assert len(cell.objects) == 2
    assert np.allclose(extents(cell), [12, 2, 2])


def test_screen_system(tmp_path):
    path = tmp_path / "b.stl"
    box((10, 20, 30)).export(path)
    cell = import_cad(path, system="S", place_at=(0, 0, 0))
    # file X, Y, Z are screen axes: X_s = Y_w, Y_s = Z_w + 26, Z_s = X_w
    assert np.allclose(extents(cell), [30, 10, 20])
    assert np.allclose(cell.objects[0].vertices.min(axis=0), [0, 0, -26])


def test_flat_mesh_gets_min_depth(tmp_path):
    path = tmp_path / "sheet.obj"
    path.write_text("v 0 0 0\nv 100 0 0\nv 100 50 0\nv 0 50 0\nf 1 2 3\nf 1 3 4\n")
    cell = import_cad(path)
    assert np.allclose(extents(cell), [100, 50, 1])
    assert any("flat" in w for w in cell.warnings)


@pytest.mark.parametrize("name, data, reason", [
    ("junk.stl", b"\x00\x01junk" * 3, "not a readable STL|no mesh geometry .*STL"),
    ("empty.obj", b"", "empty"),
    ("text.glb", b"this is not a glb file at all", "not a readable GLB"),
    ("nothing.obj", b"# only a comment\n", "no mesh geometry"),
])
def test_bad_meshes_are_refused_with_a_reason(tmp_path, name, data, reason):
    path = tmp_path / name
    path.write_bytes(data)
    with pytest.raises(CadImportError, match=reason) as info:
        import_cad(path)
    assert str(info.value).startswith(str(path) + ":")


def test_degenerate_mesh(tmp_path):
    path = tmp_path / "line.obj"
    path.write_text("v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n")
    with pytest.raises(CadImportError, match="one line|no mesh geometry"):
        import_cad(path)
