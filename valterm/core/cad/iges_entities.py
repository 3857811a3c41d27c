"""The entities of an IGES file as its directory and parameter sections describe them.

Shared by the reader (``iges.py``) and the geometry walker (``iges_geometry.py``), so that
neither imports the other's module: the reader uses the walker, one direction only.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

import numpy as np

from valterm.core.cad.errors import CadImportError


class Hollerith(str):
    """A string parameter (``nH...``), told apart from numbers."""


@dataclass
class Entity:
    """One directory entry, with its parameters once read."""

    seq: int                  # directory sequence number of its first line (odd)
    line: int                 # file line of that directory line
    type: int
    param_ptr: int
    level: int
    matrix_ptr: int
    status: str
    form: int
    param_count: int
    label: str
    params: list[str] = field(default_factory=list)
    param_lines: list[int] = field(default_factory=list)   # file line of each parameter's start

    @property
    def subordinate(self) -> int:
        s = self.status.replace(" ", "0").rjust(8, "0")
        return int(s[2:4]) if s[2:4].isdigit() else 0

    @property
    def use(self) -> int:
        s = self.status.replace(" ", "0").rjust(8, "0")
        return int(s[4:6]) if s[4:6].isdigit() else 0


# entity types never drawn as geometry: annotation, structure, properties, views, drawings
NON_GEOMETRY = set(range(200, 300)) | {0, 124, 134, 125, 302, 304, 306, 308, 310, 312, 314, 316, 320,
                                        322, 402, 404, 406, 410, 420, 430}




class EntityModel(Protocol):
    """What the geometry walker reads of a model (``IgesModel`` is one)."""

    entities: dict[int, Entity]
    path: Path
    mm_per_unit: float
    scale: float
    warnings: list[str]

    def error(self, line: int | None, reason: str) -> CadImportError: ...
    def num(self, ent: Entity, i: int, default: float | None = None) -> float: ...
    def nums(self, ent: Entity, start: int, count: int) -> np.ndarray: ...
    def integer(self, ent: Entity, i: int, default: int | None = None) -> int: ...
    def pointer(self, ent: Entity, i: int, optional: bool = False) -> Entity | None: ...
    def matrix(self, ent: Entity, _depth: int = 0) -> np.ndarray: ...
