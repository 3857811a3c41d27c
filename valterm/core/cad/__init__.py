"""CAD import (IGES, polygon meshes) into extruded convex polyhedra, and GLB/OBJ/STL export.

Public API: ``import_cad`` (placed by ``place_on_table``), ``add_parts``, ``native_units``,
``CadImportError``, ``read_iges``, ``read_mesh_parts``, ``extruded_hull``, ``export_scene``,
``CadExportError``. Nothing here imports textual or rich.
"""

from valterm.core.cad.convert import add_parts, import_cad, native_units, scs_to_world, setup_name, summary
from valterm.core.cad.errors import CadExportError, CadImportError, DegeneratePart
from valterm.core.cad.export import export_scene, polyhedron_mesh
from valterm.core.cad.hull import extruded_hull
from valterm.core.cad.iges import IgesModel, Part, read_iges
from valterm.core.cad.mesh import read_mesh_parts
from valterm.core.cad.placement import place_on_table

__all__ = ["CadExportError", "CadImportError", "DegeneratePart", "IgesModel", "Part", "add_parts",
           "export_scene", "extruded_hull", "import_cad", "native_units", "place_on_table",
           "polyhedron_mesh", "read_iges", "read_mesh_parts", "scs_to_world", "setup_name", "summary"]
