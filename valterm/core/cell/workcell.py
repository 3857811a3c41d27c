"""The work cell: the user-defined objects (workpieces, fixtures) numbered 1..n."""

from __future__ import annotations

from dataclasses import dataclass, field

from valterm.core.cell.polyhedron import Polyhedron


@dataclass
class WorkCell:
    """The objects of a setup file, in world millimetres, numbered 1..n in file order.

    ``units`` and ``system`` are what the setup file said (MM/IN, W/S), kept so a write
    round-trips; the vertices are always world millimetres.
    """

    objects: list[Polyhedron] = field(default_factory=list)
    units: str = "MM"
    system: str = "W"
    name: str = ""
    warnings: list[str] = field(default_factory=list)

    def object(self, number: int) -> Polyhedron:
        """Object by its 1-based number."""
        if not 1 <= number <= len(self.objects):
            raise IndexError(f"there is no part {number} (the cell has {len(self.objects)})")
        return self.objects[number - 1]
