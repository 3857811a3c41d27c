"""CAD import (IGES, polygon meshes) into extruded convex polyhedra, and GLB/OBJ/STL export.

Public API: ``import_cad`` (placed by ``place_on_table``), ``add_parts``, ``native_units``,
``CadImportError``, ``read_iges``, ``read_mesh_parts``, ``extruded_hull``, ``export_scene``,
``CadExportError``. Nothing here imports textual or rich.
"""

from importlib import import_module
from typing import Any

# where each public name lives: a name loads its module when first used, so that importing
# one module of the package (``valterm.core.cad.export`` at start) does not load the readers
_HOME = {
    "add_parts": "convert", "import_cad": "convert", "native_units": "convert", "scs_to_world": "convert",
    "setup_name": "convert", "summary": "convert", "CadExportError": "errors", "CadImportError": "errors",
    "DegeneratePart": "errors", "export_scene": "export", "polyhedron_mesh": "export",
    "extruded_hull": "hull", "IgesModel": "iges", "Part": "iges", "read_iges": "iges",
    "read_mesh_parts": "mesh", "place_on_table": "placement",
}


def __getattr__(name: str) -> Any:
    home = _HOME.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(import_module(f"{__name__}.{home}"), name)


__all__ = ["CadExportError", "CadImportError", "DegeneratePart", "IgesModel", "Part", "add_parts",
           "export_scene", "extruded_hull", "import_cad", "native_units", "place_on_table",
           "polyhedron_mesh", "read_iges", "read_mesh_parts", "scs_to_world", "setup_name", "summary"]
