"""CAD import (IGES, polygon meshes) into extruded convex polyhedra, and GLB/OBJ/STL export.

Import each name from the module it lives in, so that using one (``export`` at start) loads
none of the readers (issue 25, the start) and tools see every arrow (issue 37):

- ``convert``: ``import_cad``, ``add_parts``, ``native_units``, ``scs_to_world``, ``setup_name``, ``summary``
- ``errors``: ``CadImportError``, ``CadExportError``, ``DegeneratePart``
- ``export``: ``export_scene``, ``polyhedron_mesh``
- ``hull``: ``extruded_hull``
- ``iges``: ``read_iges``, ``IgesModel``, ``Part``
- ``mesh``: ``read_mesh_parts``
- ``placement``: ``place_on_table``

Nothing here imports textual or rich.
"""
