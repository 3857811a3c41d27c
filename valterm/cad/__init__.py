"""CAD import (IGES, polygon meshes) into extruded convex polyhedra, and OBJ/GLB export.

Public API: ``import_cad``, ``CadImportError``, ``read_iges``, ``read_mesh_parts``,
``extruded_hull``, ``export_scene``. Nothing here imports textual or rich.
"""

from valterm.cad.convert import import_cad, scs_to_world, setup_name, summary
from valterm.cad.errors import CadImportError, DegeneratePart
from valterm.cad.export import export_scene, polyhedron_mesh
from valterm.cad.hull import extruded_hull
from valterm.cad.iges import IgesModel, Part, read_iges
from valterm.cad.mesh import read_mesh_parts

__all__ = ["CadImportError", "DegeneratePart", "IgesModel", "Part", "export_scene", "extruded_hull",
           "import_cad", "polyhedron_mesh", "read_iges", "read_mesh_parts", "scs_to_world",
           "setup_name", "summary"]
