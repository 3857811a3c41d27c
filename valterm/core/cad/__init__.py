"""CAD import (IGES, polygon meshes) into extruded convex polyhedra, and OBJ/GLB export.

Public API: ``import_cad``, ``CadImportError``, ``read_iges``, ``read_mesh_parts``,
``extruded_hull``, ``export_scene``. Nothing here imports textual or rich.
"""

from valterm.core.cad.convert import import_cad, scs_to_world, setup_name, summary
from valterm.core.cad.errors import CadImportError, DegeneratePart
from valterm.core.cad.export import export_scene, polyhedron_mesh
from valterm.core.cad.hull import extruded_hull
from valterm.core.cad.iges import IgesModel, Part, read_iges
from valterm.core.cad.mesh import read_mesh_parts

__all__ = ["CadImportError", "DegeneratePart", "IgesModel", "Part", "export_scene", "extruded_hull",
           "import_cad", "polyhedron_mesh", "read_iges", "read_mesh_parts", "scs_to_world",
           "setup_name", "summary"]
