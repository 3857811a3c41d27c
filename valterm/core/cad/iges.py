"""IGES reader (ANSI Y14.26M / IGES 5.3, fixed 80-column ASCII form) -> 3-D points per part.

Only what an extruded-convex-hull envelope needs is read: the points of every geometric entity,
in model space, in millimetres. Parsing follows the standard's layout:

* every line is 80 columns; column 73 holds the section letter (S, G, D, P, T) and columns
  74-80 the sequence number within the section;
* Global (G): free-format parameters with the declared parameter and record delimiters
  (fields 1 and 2, default ``,`` and ``;``), Hollerith strings ``nH...``; field 13 model-space
  scale, field 14 units flag, field 15 units name;
* Directory (D): two lines of ten 8-column fields per entity;
* Parameter (P): columns 1-64 joined over the entity's lines, columns 66-72 point back to the
  entity's directory line.

Parts (the "workpieces" of §7.1): entities are grouped by their level (directory field 5),
the classical CAD layer. A file that uses one level is one part. ``IgesModel.parts(n)`` can
instead split the file into its n spatially separate bodies, or merge it into one part.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from valterm.core.cad.errors import CadImportError, read_cad_bytes
from valterm.core.cad.iges_entities import Entity, Hollerith
from valterm.core.cad.iges_geometry import Walker

# units flag (global field 14) -> millimetres per model unit
UNIT_MM: dict[int, float] = {1: 25.4, 2: 1.0, 4: 304.8, 5: 1_609_344.0, 6: 1000.0, 7: 1_000_000.0,
                             8: 0.0254, 9: 0.001, 10: 10.0, 11: 2.54e-5}
UNIT_NAMES: dict[str, float] = {"IN": 25.4, "INCH": 25.4, "MM": 1.0, "FT": 304.8, "MI": 1_609_344.0,
                                "M": 1000.0, "KM": 1_000_000.0, "MIL": 0.0254, "UM": 0.001,
                                "CM": 10.0, "UIN": 2.54e-5}

ARC_SAMPLES_PER_TURN = 64
# entity labels some writers give by kind: they say what an entity is, not which part
GENERIC_LABELS = {"POINT", "LINE", "ARC", "CIRCLE", "CURVE", "SPLINE", "SURFACE", "PLANE", "FACE",
                  "SHELL", "SOLID", "EDGE", "VERTEX", "LOOP", "MATRIX", "TRANSFRM", "COMPOSIT",
                  "ATT_TBLE", "3DSKETCH", "SKETCH"}
_HOLLERITH = re.compile(r"\s*(\d+)H")
_SECTIONS = "SGDPT"


@dataclass
class Part:
    """The points (mm) of one workpiece and where they came from."""

    name: str
    points: np.ndarray
    entities: list[int]


class IgesModel:
    """A parsed IGES file: global parameters, entities by directory sequence number."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.global_params: list[str] = []
        self.global_lines: list[int] = []  # the file line of each global parameter
        self.entities: dict[int, Entity] = {}
        self.warnings: list[str] = []
        self._read()

    # ------------------------------------------------------------------ errors
    def error(self, line: int | None, reason: str) -> CadImportError:
        return CadImportError(self.path, line, reason)

    # ------------------------------------------------------------------ reading
    def _read(self) -> None:
        raw = read_cad_bytes(self.path)  # the one read path: a FIFO or a device is refused
        if not raw.strip():
            raise self.error(None, "the file is empty")
        text = raw.decode("latin-1")
        lines = text.split("\n")
        if lines and lines[-1].strip() in ("", "\x1a"):
            lines.pop()  # final newline (or a DOS end-of-file mark)
        sections: dict[str, list[tuple[int, str]]] = {s: [] for s in _SECTIONS}
        order = ""
        for number, line in enumerate(lines, 1):
            line = self._card(number, line.rstrip("\r"))
            letter = line[72]
            if not order or order[-1] != letter:
                if letter in order or (order and _SECTIONS.index(letter) < _SECTIONS.index(order[-1])):
                    raise self.error(number, f"section {letter} out of order (sections run S, G, D, P, T)")
                order += letter
            seq_text = line[73:80].strip()
            if not seq_text.isdigit():
                raise self.error(number, f"sequence number {line[73:80]!r} in columns 74-80 is not a number")
            expected = len(sections[letter]) + 1
            if int(seq_text) != expected:
                raise self.error(number, f"sequence number {int(seq_text)} of section {letter}, expected {expected}")
            sections[letter].append((number, line))
        for letter, name in (("G", "Global"), ("D", "Directory"), ("P", "Parameter"), ("T", "Terminate")):
            if not sections[letter]:
                at = len(lines) if letter == "T" else None
                hint = ": the file is truncated" if letter == "T" else ""
                raise self.error(at, f"no {name} ({letter}) section{hint}")
        if not sections["S"]:
            self.warnings.append(f"{self.path.name}: no Start (S) section")
        self._read_global(sections["G"])
        self._read_directory(sections["D"], len(sections["P"]))
        self._read_parameters(sections["P"])

    def _card(self, number: int, line: str) -> str:
        """One line of the file as an 80-column card of a section (S, G, D, P, T), or why not."""
        bad = re.search(r"[\x00-\x08\x0b-\x1f\x7f-\x9f]", line)
        if bad:
            raise self.error(number, f"binary data (byte 0x{ord(bad.group()):02x} in column {bad.start() + 1}): "
                                     "not an ASCII IGES file")
        if len(line) != 80:
            if len(line) > 72 and line[72] == "T" and len(line.rstrip()) <= 80:
                line = line.ljust(80)  # some writers trim the blanks off the last line
            else:
                raise self.error(number, f"line is {len(line)} columns long; IGES lines have 80")
        letter = line[72]
        if letter in "BC":
            raise self.error(number, "binary or compressed IGES is not supported (export ASCII IGES)")
        if letter not in _SECTIONS:
            raise self.error(number, f"column 73 holds {letter!r}, not a section letter (S, G, D, P, T)")
        return line

    def _tokens(self, chunks: list[tuple[int, str]], pdelim: str, rdelim: str, start: int = 0,
                ) -> tuple[list[str], list[int]]:
        """Free-format parameters of text joined from (file line, text) chunks of equal width."""
        width = len(chunks[0][1])
        text = "".join(c for _, c in chunks)

        def line_at(pos: int) -> int:
            return chunks[min(pos // width, len(chunks) - 1)][0]

        out: list[str] = []
        where: list[int] = []
        pos = start
        n = len(text)
        while True:
            m = _HOLLERITH.match(text, pos)
            if m:
                count = int(m.group(1))
                body = text[m.end():m.end() + count]
                if len(body) < count:
                    raise self.error(line_at(pos), f"string {m.group(1)}H... runs past the end of its record")
                out.append(Hollerith(body))
                where.append(line_at(pos))
                pos = m.end() + count
                while pos < n and text[pos] == " ":
                    pos += 1
                if pos >= n:
                    raise self.error(line_at(n - 1), f"record does not end with {rdelim!r}")
                if text[pos] not in (pdelim, rdelim):
                    raise self.error(line_at(pos), f"string parameter not followed by {pdelim!r} or {rdelim!r}")
            else:
                ends = [i for i in (text.find(pdelim, pos), text.find(rdelim, pos)) if i >= 0]
                if not ends:
                    raise self.error(line_at(n - 1), f"record does not end with {rdelim!r}")
                end = min(ends)
                out.append(text[pos:end].strip())
                where.append(line_at(pos))
                pos = end
            if text[pos] == rdelim:
                return out, where
            pos += 1

    def _read_global(self, lines: list[tuple[int, str]]) -> None:
        chunks = [(n, text[:72]) for n, text in lines]
        text = "".join(c for _, c in chunks)
        pdelim, rdelim, pos = ",", ";", 0
        # fields 1 and 2 declare the delimiters themselves, so read them by hand
        if text.startswith("1H"):
            pdelim, pos = text[2], 3
        if text[pos:pos + 1] != pdelim:
            raise self.error(lines[0][0], f"global section: expected the parameter delimiter {pdelim!r} after field 1")
        pos += 1
        if text.startswith("1H", pos):
            rdelim, pos = text[pos + 2], pos + 3
            if text[pos:pos + 1] not in (pdelim, rdelim):
                raise self.error(lines[0][0], "global section: field 2 not followed by a delimiter")
            if text[pos] == pdelim:
                pos += 1
        elif text[pos:pos + 1] == pdelim:
            pos += 1
        if pdelim == rdelim or pdelim in " 0123456789H+-.":
            raise self.error(lines[0][0], f"global section: unusable delimiters {pdelim!r} and {rdelim!r}")
        self.pdelim, self.rdelim = pdelim, rdelim
        rest: list[str] = []
        rest_lines: list[int] = []
        if text[pos - 1:pos] != rdelim:
            rest, rest_lines = self._tokens(chunks, pdelim, rdelim, pos)
        self.global_params = [pdelim, rdelim, *rest]
        self.global_lines = [lines[0][0], lines[0][0], *rest_lines]
        self._read_units()

    def _global(self, index: int) -> str:
        return self.global_params[index - 1] if len(self.global_params) >= index else ""

    def _global_number(self, index: int, default: float) -> float:
        raw = self._global(index)
        if raw == "" or isinstance(raw, Hollerith):
            return default
        try:
            return float(raw.replace("D", "E").replace("d", "e"))
        except ValueError:
            raise self.error(self.global_lines[index - 1], f"global field {index}: bad number {raw!r}") from None

    def _read_units(self) -> None:
        self.scale = self._global_number(13, 1.0)
        flag = int(self._global_number(14, 1.0))
        name = str(self._global(15)).strip().upper()
        if flag == 3:
            if name not in UNIT_NAMES:
                raise self.error(self.global_lines[14] if len(self.global_lines) > 14 else None,
                                 f"global field 15: unknown units name {name!r}")
            self.mm_per_unit = UNIT_NAMES[name]
        elif flag in UNIT_MM:
            self.mm_per_unit = UNIT_MM[flag]
        else:
            raise self.error(self.global_lines[13] if len(self.global_lines) > 13 else None,
                             f"global field 14: unknown units flag {flag}")
        if self.scale <= 0:
            raise self.error(self.global_lines[12],
                             f"global field 13: model space scale {self.scale:g} must be positive")
        self.units_flag = flag
        self.units_name = name

    @property
    def file_units(self) -> str:
        """``IN`` or ``MM``: how a setup file of this model would naturally be written."""
        return "IN" if self.mm_per_unit == 25.4 else "MM"

    def _read_directory(self, lines: list[tuple[int, str]], p_count: int) -> None:
        if len(lines) % 2:
            raise self.error(lines[-1][0], "directory section has an odd number of lines (entries take two)")
        for i in range(0, len(lines), 2):
            (n1, l1), (n2, l2) = lines[i], lines[i + 1]
            f1 = [l1[j:j + 8] for j in range(0, 72, 8)]
            f2 = [l2[j:j + 8] for j in range(0, 72, 8)]

            def num(text: str, line: int, col: int, what: str) -> int:
                t = text.strip()
                if not t:
                    return 0
                try:
                    return int(t)
                except ValueError:
                    raise self.error(
                        line, f"directory field {what} (columns {col}-{col + 7}): {t!r} is not an integer") from None

            etype = num(f1[0], n1, 1, "1 entity type")
            etype2 = num(f2[0], n2, 1, "11 entity type")
            if etype != etype2:
                raise self.error(n2, f"directory entry: entity type {etype2} on line 2, {etype} on line 1")
            ptr = num(f1[1], n1, 9, "2 parameter pointer")
            if not 1 <= ptr <= p_count:
                raise self.error(n1, f"parameter pointer {ptr} out of range (the P section has {p_count} lines)")
            count = num(f2[3], n2, 25, "14 parameter line count")
            if count < 1 or ptr + count - 1 > p_count:
                raise self.error(n2, f"parameter line count {count} out of range (from line {ptr} of {p_count})")
            seq = i + 1
            self.entities[seq] = Entity(
                seq=seq, line=n1, type=etype, param_ptr=ptr, level=num(f1[4], n1, 33, "5 level"),
                matrix_ptr=num(f1[6], n1, 49, "7 transformation matrix"), status=f1[8],
                form=num(f2[4], n2, 33, "15 form"), param_count=count, label=f2[7].strip())
        for ent in self.entities.values():
            if ent.matrix_ptr and (ent.matrix_ptr not in self.entities or self.entities[ent.matrix_ptr].type != 124):
                raise self.error(ent.line,
                                 f"transformation matrix pointer {ent.matrix_ptr} does not point to a 124 entity")

    def _read_parameters(self, lines: list[tuple[int, str]]) -> None:
        for ent in self.entities.values():
            chunk = lines[ent.param_ptr - 1: ent.param_ptr - 1 + ent.param_count]
            for number, line in chunk:
                back = line[64:72].strip()
                if not back.isdigit() or int(back) != ent.seq:
                    raise self.error(number,
                                     f"parameter line belongs to directory entry {back or '?'}, expected {ent.seq}")
            params, where = self._tokens([(n, text[:64]) for n, text in chunk], self.pdelim, self.rdelim)
            try:
                head = int(float(params[0]))
            except (ValueError, IndexError):
                raise self.error(chunk[0][0],
                                 f"parameter data starts with {params[0]!r}, not the entity type") from None
            if head != ent.type:
                raise self.error(chunk[0][0],
                                 f"parameter data is for entity type {head}, the directory says {ent.type}")
            ent.params, ent.param_lines = params[1:], where[1:]

    # ------------------------------------------------------------------ parameters
    def num(self, ent: Entity, i: int, default: float | None = None) -> float:
        """Parameter i (1-based, after the type) as a number."""
        if i > len(ent.params) or ent.params[i - 1] == "":
            if default is not None:
                return default
            line = ent.param_lines[-1] if ent.param_lines else ent.line
            raise self.error(line, f"entity {ent.type} (D{ent.seq}): parameter {i} missing")
        raw = ent.params[i - 1]
        try:
            if isinstance(raw, Hollerith):
                raise ValueError
            value = float(raw.replace("D", "E").replace("d", "e"))
        except ValueError:
            raise self.error(ent.param_lines[i - 1], f"entity {ent.type} (D{ent.seq}): bad number {raw!r}") from None
        if not math.isfinite(value):
            raise self.error(ent.param_lines[i - 1], f"entity {ent.type} (D{ent.seq}): number {raw!r} is not finite")
        return value

    def nums(self, ent: Entity, start: int, count: int) -> np.ndarray:
        if count < 0 or start - 1 + count > len(ent.params):
            line = ent.param_lines[-1] if ent.param_lines else ent.line
            raise self.error(line, f"entity {ent.type} (D{ent.seq}): expected {start - 1 + count} parameters, "
                                   f"found {len(ent.params)}")
        return np.array([self.num(ent, i) for i in range(start, start + count)])

    def integer(self, ent: Entity, i: int, default: int | None = None) -> int:
        value = self.num(ent, i, None if default is None else float(default))
        if value != int(value):
            raise self.error(ent.param_lines[i - 1], f"entity {ent.type} (D{ent.seq}): {value:g} is not an integer")
        return int(value)

    def pointer(self, ent: Entity, i: int, optional: bool = False) -> Entity | None:
        p = self.integer(ent, i, 0 if optional else None)
        if p == 0 and optional:
            return None
        p = abs(p)  # negative pointers mark e.g. subfigure-level links; the entity is the same
        if p not in self.entities:
            line = ent.param_lines[i - 1] if i <= len(ent.param_lines) else ent.line
            raise self.error(line, f"entity {ent.type} (D{ent.seq}): pointer {p} is not a directory entry")
        return self.entities[p]

    # ------------------------------------------------------------------ transforms
    def matrix(self, ent: Entity, _depth: int = 0) -> np.ndarray:
        """4x4 model-space transform of an entity: its matrix, then the chain of that matrix's own."""
        if not ent.matrix_ptr:
            return np.eye(4)
        if _depth > 64:
            raise self.error(ent.line, "transformation matrices chain in a circle")
        t = self.entities[ent.matrix_ptr]
        v = self.nums(t, 1, 12).reshape(3, 4)
        m = np.eye(4)
        m[:3, :] = v
        return self.matrix(t, _depth + 1) @ m

    # ------------------------------------------------------------------ parts
    def model_points(self) -> dict[int, np.ndarray]:
        """Model-space points (mm) of every top-level entity, by directory sequence number."""
        return Walker(self).run()

    def parts(self, count: int | None = None) -> list[Part]:
        """The workpieces: by level, or (``count`` given) merged into one or split into bodies."""
        points = self.model_points()
        if not points:
            raise self.error(None, "no geometry that can be drawn (no points, curves or surfaces found)")
        stem = self.path.stem.upper()
        by_level: dict[int, list[int]] = {}
        for seq in points:
            by_level.setdefault(self.entities[seq].level, []).append(seq)

        def part(name: str, seqs: list[int]) -> Part:
            return Part(self.label_of(seqs) or name, np.concatenate([points[s] for s in seqs]), seqs)

        if count == 1:
            return [part(stem, list(points))]
        if count is None or count == len(by_level):
            if len(by_level) == 1:
                return [part(stem, list(points))]
            return [part(f"{stem} L{lv}", seqs) for lv, seqs in sorted(by_level.items())]
        bodies = separate_bodies(points)
        if count == len(bodies):
            return [part(f"{stem} B{i + 1}", seqs) for i, seqs in enumerate(bodies)]
        raise self.error(None, f"asked for {count} workpieces; the file holds {len(by_level)} by level "
                               f"and {len(bodies)} separate bodies")


    def label_of(self, seqs: list[int]) -> str:
        """The entity label (directory field 18) the part's entities share, if one names it.

        Labels that only repeat the entity's kind (``POINT``, ``LINE``...) name nothing."""
        labels = {self.entities[s].label.strip().upper() for s in seqs} - {""}
        return labels.pop() if len(labels) == 1 and not labels & GENERIC_LABELS else ""


def separate_bodies(points: dict[int, np.ndarray]) -> list[list[int]]:
    """Entities joined into bodies where their bounding boxes touch (union-find)."""
    seqs = list(points)
    lo = np.array([points[s].min(axis=0) for s in seqs])
    hi = np.array([points[s].max(axis=0) for s in seqs])
    tol = 1e-6 * float(np.ptp(np.concatenate([lo, hi]), axis=0).max() or 1.0)
    touch = np.all((lo[:, None, :] <= hi[None, :, :] + tol) & (lo[None, :, :] <= hi[:, None, :] + tol), axis=2)
    parent = list(range(len(seqs)))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i, j in zip(*np.nonzero(np.triu(touch, 1))):
        parent[root(int(i))] = root(int(j))
    groups: dict[int, list[int]] = {}
    for i, s in enumerate(seqs):
        groups.setdefault(root(i), []).append(s)
    return sorted(groups.values(), key=lambda g: g[0])


def read_iges(path: str | Path) -> IgesModel:
    """Parse an IGES file; raises ``CadImportError`` (``file:line: reason``) on bad input."""
    return IgesModel(path)
