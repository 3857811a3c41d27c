"""CAD that round-trips (issue 24): one axis convention for glTF in and out, a unit guess,
a triangle limit, located messages for malformed meshes, STL read with numpy."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from app_helpers import sync

from valterm.cli import main as cli
from valterm.core.cad.convert import import_cad
from valterm.core.cad.errors import CadImportError
from valterm.core.cad.export import export_scene
from valterm.core.cad import mesh as mesh_module
from valterm.core.cad.axes import gltf_to_world, world_to_gltf
from valterm.core.cad.mesh import distinct, read_mesh_parts
from valterm.core.cell.workcell import WorkCell


def extents(cell: WorkCell) -> np.ndarray:
    lo = np.min([p.vertices.min(axis=0) for p in cell.objects], axis=0)
    hi = np.max([p.vertices.max(axis=0) for p in cell.objects], axis=0)
    return hi - lo


def sorted_vertices(cell: WorkCell) -> list[np.ndarray]:
    return [p.vertices[np.lexsort(np.round(p.vertices, 3).T[::-1])] for p in cell.objects]


def gltf_block(path: Path) -> Path:
    """A 100 x 40 x 60 mm block (world X, Y, Z) as a CAD program writes it to glTF: metres, Y up."""
    trimesh.creation.box(extents=(0.100, 0.060, 0.040)).export(path)  # glTF x, y (up), z
    return path


def gltf_lying_cylinder(path: Path) -> Path:
    """A cylinder r 20 mm, 100 mm long, lying: its axis along glTF Z (horizontal)."""
    trimesh.creation.cylinder(radius=0.020, height=0.100, sections=24).export(path)
    return path


def test_the_axis_convention_is_one_rotation_and_its_inverse() -> None:
    points = np.array([[1.0, 2.0, 3.0], [-4.0, 5.0, -6.0]])
    assert np.allclose(world_to_gltf(points), [[1, 3, -2], [-4, -6, -5]])  # up: world Z -> glTF Y
    assert np.allclose(gltf_to_world(world_to_gltf(points)), points)


@pytest.mark.parametrize("make, size", [(gltf_block, [100, 40, 60]), (gltf_lying_cylinder, [40, 100, 40])])
def test_gltf_import_export_reimport_is_unchanged(tmp_path: Path, make, size) -> None:  # type: ignore[no-untyped-def]
    first = import_cad(make(tmp_path / "part.glb"))
    assert np.allclose(extents(first), size, atol=0.01)  # the block stays 60 high; the cylinder lies
    out = export_scene(first, [], tmp_path / "again.glb")
    # what other programs read: Y up, metres
    scene = trimesh.load(out, force="scene")
    assert np.allclose(scene.extents, np.abs(world_to_gltf(np.array(size, dtype=float))) / 1000, atol=1e-5)
    second = import_cad(out)
    assert len(second.objects) == 1
    # the same place on the table, the same shape, to 0.01 mm
    for a, b in zip(sorted_vertices(first), sorted_vertices(second)):
        assert a.shape == b.shape
        assert np.abs(a - b).max() < 0.01
    # and again: export, re-import
    third = import_cad(export_scene(second, [], tmp_path / "third.glb"))
    assert np.abs(sorted_vertices(third)[0] - sorted_vertices(first)[0]).max() < 0.01


def test_screen_axes_take_a_gltfs_numbers_as_written(tmp_path: Path) -> None:
    path = gltf_block(tmp_path / "part.glb")  # glTF extents x 100, y 60, z 40 mm
    stl = tmp_path / "part.stl"
    trimesh.creation.box(extents=(100, 60, 40)).export(stl)  # the same numbers, in mm
    from_gltf = import_cad(path, system="S", place_at=(0, 0, 0))
    from_stl = import_cad(stl, system="S", place_at=(0, 0, 0))
    # X_s = Y_w, Y_s = Z_w + 26, Z_s = X_w: world extents (z, x, y) of the file's numbers
    assert np.allclose(extents(from_gltf), [40, 100, 60], atol=0.01)
    assert np.allclose(extents(from_gltf), extents(from_stl), atol=0.01)


def test_a_metre_stl_read_as_millimetres_warns_with_the_fix(tmp_path: Path) -> None:
    path = tmp_path / "link.stl"
    trimesh.creation.box(extents=(0.3, 0.1, 0.1)).export(path)  # a robot link in metres
    cell = import_cad(path)
    said = [w for w in cell.warnings if "implausibly small" in w]
    assert len(said) == 1 and "units M" in said[0] and "--units M" in said[0], cell.warnings
    assert not any("implausibly" in w for w in import_cad(path, units="M").warnings)
    big = tmp_path / "cell.stl"
    trimesh.creation.box(extents=(800, 600, 900)).export(big)
    assert not any("implausibly" in w for w in import_cad(big).warnings)
    said = [w for w in import_cad(big, units="M").warnings if "implausibly large" in w]
    assert len(said) == 1 and "--units MM" in said[0]


def test_the_triangle_limit_is_named_and_large_files_say_what_they_do(tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "ball.stl"
    trimesh.creation.icosphere(subdivisions=3, radius=50).export(path)  # 1280 triangles
    told: list[str] = []
    monkeypatch.setattr(mesh_module, "LARGE_TRIANGLES", 1000)
    monkeypatch.setattr(mesh_module, "LARGE_BYTES", 1000)
    cell = import_cad(path, progress=told.append)
    assert np.allclose(extents(cell), 100, atol=1)
    assert told[0].startswith("ball.stl: reading") and "1,280 triangles read" in told[1]
    monkeypatch.setattr(mesh_module, "MAX_TRIANGLES", 1000)
    with pytest.raises(CadImportError, match="1,280 triangles: more than the import limit of 1,000"):
        import_cad(path)
    obj = tmp_path / "ball.obj"
    trimesh.creation.icosphere(subdivisions=3, radius=50).export(obj)
    with pytest.raises(CadImportError, match="1,280 faces: more than the import limit of 1,000"):
        import_cad(obj)


def test_binary_and_ascii_stl_read_by_numpy_match_trimesh(tmp_path: Path) -> None:
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=30)
    sphere.apply_translation([5, 6, 7])
    for kind in ("binary", "ascii"):
        path = tmp_path / f"s-{kind}.stl"
        path.write_bytes(trimesh.exchange.stl.export_stl(sphere) if kind == "binary"
                         else trimesh.exchange.stl.export_stl_ascii(sphere).encode())
        (part,) = read_mesh_parts(path)
        assert part.name == f"s-{kind}"
        assert len(part.points) == len(sphere.vertices)  # each shared vertex once
        assert np.allclose(np.sort(part.points, axis=0), np.sort(sphere.vertices, axis=0), atol=1e-4)


def test_distinct_rows_once_each_and_minus_zero_is_zero() -> None:
    rows = np.array([[1, 2, 3], [1, 2, 3], [3, 2, 1], [0, 0, 0], [1, 2, 3], [-0.0, 0, -0.0]], dtype=np.float32)
    assert sorted(map(tuple, distinct(rows))) == [(0, 0, 0), (1, 2, 3), (3, 2, 1)]
    rng = np.random.default_rng(5)
    many = rng.integers(0, 40, (20000, 3)).astype(float) / 4  # few distinct values: many repeats
    assert len(distinct(many)) == len(np.unique(many, axis=0))


@pytest.mark.slow  # CI runs it (pytest -m slow); the default run stays under 5 minutes
def test_a_two_million_triangle_stl_imports(tmp_path: Path) -> None:
    """The size the issue measured (50 s and 2.9 GB with trimesh): read by numpy, envelope of
    the distinct vertices. Its time and memory are `valterm bench`'s, not a test's."""
    from valterm.bench.cad import torus_stl

    path = tmp_path / "torus.stl"
    assert torus_stl(path) == 2_000_000
    cell = import_cad(path)
    assert np.allclose(extents(cell), [210, 210, 50], atol=0.5)


# -- malformed meshes: one located line, no library traceback --------------------------------------
def _gltf_with(tmp_path: Path, change) -> Path:  # type: ignore[no-untyped-def]
    files = trimesh.Scene(trimesh.creation.box(extents=(0.1, 0.1, 0.1))).export(file_type="gltf")
    for name, data in files.items():
        (tmp_path / name).write_bytes(data)
    document = json.loads(files["model.gltf"])
    change(document)
    (tmp_path / "model.gltf").write_text(json.dumps(document))
    return tmp_path / "model.gltf"


def _remote(document: dict) -> None:
    document["buffers"][0]["uri"] = "https://example.com/model.bin"


def _missing(document: dict) -> None:
    document["buffers"][0]["uri"] = "gone.bin"


def _draco(document: dict) -> None:
    document["extensionsRequired"] = document["extensionsUsed"] = ["KHR_draco_mesh_compression"]


@pytest.mark.parametrize("name, data, said", [
    ("two.obj", b"v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", "two.obj:2: a vertex needs three numbers"),
    ("bad.stl", b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\nvertex 1 0 0\nvertex 0 1 0\n",
     "bad.stl:4: a vertex needs three numbers"),
    ("word.stl", b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 x 0\n   vertex 0 1 0\n",
     "word.stl:5: a vertex coordinate is not a number"),
    ("cut.stl", b"\0" * 80 + (1000).to_bytes(4, "little") + b"\1" * 100, "a binary STL cut short, its header says 1,000"),
    ("junk.ply", b"ply\nformat nonsense\n", "not a readable PLY mesh"),
    ("junk.glb", b"glTF\x02\0\0\0" + b"\0" * 40, "not a readable GLB mesh"),
])
def test_malformed_meshes_are_one_located_line(tmp_path: Path, name: str, data: bytes, said: str) -> None:
    path = tmp_path / name
    path.write_bytes(data)
    result = subprocess.run([sys.executable, "-m", "valterm", "--workspace", str(tmp_path / "ws"), "import",
                             str(path), "--out", "T"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 1
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and said in lines[0], result.stderr
    assert "Traceback" not in result.stderr and not (tmp_path / "ws" / "T.SET").exists()


@pytest.mark.parametrize("change, said", [
    (_remote, "its data is on the web (https://example.com/model.bin)"),
    (_missing, "its data file gone.bin is not beside it"),
    (_draco, "needs the glTF extension KHR_draco_mesh_compression"),
])
def test_gltf_refusals_speak_to_the_user_not_to_a_programmer(tmp_path: Path, change, said: str,  # type: ignore[no-untyped-def]
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    path = _gltf_with(tmp_path, change)
    assert cli(["--workspace", str(tmp_path / "ws"), "import", str(path), "--out", "T"]) == 1
    err = capsys.readouterr().err
    assert said in err and "=" not in err and "`" not in err


@sync
async def test_the_app_says_it_is_reading_a_large_mesh_before_it_does(tmp_path: Path,
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    from app_helpers import make_app, screen_text

    from valterm.core.workspace import Workspace

    Workspace.open(tmp_path)
    trimesh.creation.icosphere(subdivisions=3, radius=50).export(tmp_path / "BALL.STL")
    monkeypatch.setattr(mesh_module, "LARGE_BYTES", 1000)  # "large" for the test
    app = make_app(tmp_path, start=True)
    async with app.run_test(size=(160, 50)) as pilot:
        await pilot.press("U", *"BALL.STL", "enter", *"BALL", "enter", "1", "enter", "enter", "enter")
        await pilot.pause()
        text = screen_text(app)
        assert "READING BALL.STL (0 MB): THIS TAKES A FEW SECONDS" in text
        await pilot.pause()
        assert "BALL.SET HAS SUCCESSFULLY BEEN WRITTEN" in screen_text(app)
    assert (tmp_path / "BALL.SET").is_file()
