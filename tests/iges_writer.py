"""A small IGES writer for the tests, and the project's own IGES sample files.

`iges_text` writes the fixed 80-column form (IGES 5.3): Start, Global, Directory Entry (two
lines per entity), Parameter Data (columns 1-64, the entity's directory line in 66-72) and
Terminate, each line numbered within its section. Entity i sits at directory line 2i+1, which
is the number other entities use to point at it.

The samples in tests/data/iges/ are written by `write_samples`; they use the same entity types
and header fields as the CAD-written files in ../shared/iges-samples (see the README there),
with geometry of the project's own whose extents are worked out by hand below. Regenerate with
`python tests/iges_writer.py` (tests/test_iges_samples.py checks the bytes stay the same).
"""

from __future__ import annotations

import math
import os
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import pytest

DATA = Path(__file__).resolve().parent / "data" / "iges"


def _shared_samples() -> Path:
    """../shared/iges-samples beside the checkout; VALTERM_IGES_SAMPLES points elsewhere (or nowhere)."""
    if "VALTERM_IGES_SAMPLES" in os.environ:
        return Path(os.environ["VALTERM_IGES_SAMPLES"])
    return next((up / "shared" / "iges-samples" for up in Path(__file__).resolve().parents
                 if (up / "shared" / "iges-samples").is_dir()), Path("shared/iges-samples"))


SHARED = _shared_samples()


# --------------------------------------------------------------------------- the writer

def holl(text: str) -> str:
    """A Hollerith string: nHtext."""
    return f"{len(text)}H{text}"


def fmt(value: object) -> str:
    """A parameter: integers as integers, reals always with a point, strings as given."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return str(value)
    if isinstance(value, int):
        return str(value)
    text = f"{value:.12G}"
    return text if any(c in text for c in ".E") else text + "."


def _p_chunks(tokens: list[str], pd: str, rd: str) -> list[str]:
    """Parameter tokens with their delimiters, cut into 64-column pieces between tokens."""
    record = [t + pd for t in tokens[:-1]] + [tokens[-1] + rd]
    chunks, cur = [], ""
    for tok in record:
        if len(cur) + len(tok) > 64:
            chunks.append(cur)
            cur = ""
        cur += tok
    chunks.append(cur)
    return chunks


def _global(pd: str, rd: str, declare: bool, fields: list[str]) -> list[str]:
    head = f"1H{pd}{pd}1H{rd}{pd}" if declare or (pd, rd) != (",", ";") else f"{pd}{pd}"
    text = head + pd.join(fields) + rd
    return [text[i:i + 72] for i in range(0, len(text), 72)]


def iges_text(entities: list[dict], *, start: str = "made by the valterm tests", units_flag: int = 2,
              units_name: str = "2HMM", scale: str = "1.0", delims: tuple[str, str] = (",", ";"),
              declare: bool = False, stamp: str = "15H20240101.000000", names: str = "4Htest") -> str:
    """An 80-column IGES file. Entity dicts: type, params (list), matrix/form/level/status/label optional."""
    pd, rd = delims
    fields = [names, "8Htest.igs", names, names, "32", "38", "6", "308", "15", names, scale,
              str(units_flag), units_name, "1", "0.01", stamp, "1E-07", "100.0",
              names, names, "11", "0", stamp]
    glines = _global(pd, rd, declare, fields)
    d_lines: list[str] = []
    p_lines: list[str] = []
    for i, ent in enumerate(entities):
        seq = 2 * i + 1
        chunks = _p_chunks([str(ent["type"])] + [fmt(p) for p in ent["params"]], pd, rd)
        first = len(p_lines) + 1
        p_lines += [f"{c:<64} {seq:>7}" for c in chunks]
        status = ent.get("status", "00000000")
        d_lines.append(f"{ent['type']:>8}{first:>8}{0:>8}{0:>8}{ent.get('level', 0):>8}{0:>8}"
                       f"{ent.get('matrix', 0):>8}{0:>8}{status:>8}")
        d_lines.append(f"{ent['type']:>8}{0:>8}{0:>8}{len(chunks):>8}{ent.get('form', 0):>8}"
                       f"{'':>8}{'':>8}{ent.get('label', ''):>8}{0:>8}")
    s_lines = [start[i:i + 72] for i in range(0, len(start), 72)]
    out = [f"{s:<72}S{i:>7}" for i, s in enumerate(s_lines, 1)]
    out += [f"{g:<72}G{i:>7}" for i, g in enumerate(glines, 1)]
    out += [f"{d:<72}D{i:>7}" for i, d in enumerate(d_lines, 1)]
    out += [f"{p:<72}P{i:>7}" for i, p in enumerate(p_lines, 1)]
    out.append(f"S{len(s_lines):>7}G{len(glines):>7}D{len(d_lines):>7}P{len(p_lines):>7}".ljust(72) + f"T{1:>7}")
    assert all(len(line) == 80 for line in out)
    return "\n".join(out) + "\n"


def make_iges(entities: list[dict], units_flag: int = 2, units_name: str = "2HMM", scale: str = "1.0",
              delims: tuple[str, str] = (",", ";")) -> str:
    """The synthetic files of tests/test_cad_iges.py (parameters written as str() gives them)."""
    as_given = [dict(e, params=[str(p) for p in e["params"]]) for e in entities]
    return iges_text(as_given, units_flag=units_flag, units_name=units_name, scale=scale, delims=delims)


@dataclass
class Builder:
    """Entities in order; `add` answers the directory pointer the others use to reach it."""

    entities: list[dict] = field(default_factory=list)

    def add(self, kind: int, params: list[object], **directory: object) -> int:
        self.entities.append({"type": kind, "params": params, **directory})
        return 2 * len(self.entities) - 1


def entity_tally(text: str) -> Counter[int]:
    """Entity type numbers counted from a file's Directory Entry section (its odd lines)."""
    d_lines = [line for line in text.splitlines() if line[72:73] == "D"]
    return Counter(int(line[:8]) for line in d_lines[::2])


# --------------------------------------------------------------------------- the project's samples

OCCT_STATUS = {"curve": "00020000", "dependent": "00010000", "on_surface": "00010500", "face": "00020000"}


def rotation_z(degrees: float, shift: tuple[float, float, float]) -> list[object]:
    """A 124 matrix: turn about Z, then shift (rows R11 R12 R13 T1 ...)."""
    c, s = round(math.cos(math.radians(degrees)), 12), round(math.sin(math.radians(degrees)), 12)
    return [c, -s, 0, shift[0], s, c, 0, shift[1], 0, 0, 1, shift[2]]


def box_sample() -> str:
    """A 60 mm cube centred on (10, 20, 30) as six trimmed planes (144/108/142/102/110), like
    a solid modeller's box: model x -20..40, y -10..50, z 0..60, millimetres."""
    lo, hi = (-20.0, -10.0, 0.0), (40.0, 50.0, 60.0)
    b = Builder()
    faces = []
    for axis in range(3):
        for side, at in ((-1, lo[axis]), (1, hi[axis])):
            u, v = (axis + 1) % 3, (axis + 2) % 3
            corners = []
            for cu, cv in ((lo[u], lo[v]), (hi[u], lo[v]), (hi[u], hi[v]), (lo[u], hi[v])):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[v] = at, cu, cv
                corners.append(p)
            edges = [b.add(110, corners[i] + corners[(i + 1) % 4], status=OCCT_STATUS["dependent"])
                     for i in range(4)]
            loop = b.add(102, [4, *edges], status=OCCT_STATUS["dependent"])
            normal = [0.0, 0.0, 0.0]
            normal[axis] = float(side)
            plane = b.add(108, [*normal, side * at, 0, 0.0, 0.0, 0.0, 0.0], status=OCCT_STATUS["dependent"])
            curve = b.add(142, [1, plane, 0, loop, 2], status=OCCT_STATUS["on_surface"])
            faces.append(b.add(144, [plane, 1, 0, curve], status=OCCT_STATUS["face"]))
    b.add(402, [len(faces), *faces], form=1)
    return iges_text(b.entities, start="valterm test sample: a 60 mm cube as trimmed planes",
                     scale="1.", names=holl("valterm tests"), stamp=holl("20260101.000000"))


def wireframe_sample() -> str:
    """A wireframe frame in INCHES (110 lines, 100 arcs placed by 124 matrices, a 314 colour and
    402 groups), delimiters declared in the header. The frame is x 0..72, y 0..20, z 0..8 in;
    an arch of radius 10 stands at x = 36 (z up to 18); a half circle of radius 10 at the
    x = 0 end, lifted to z = 8, bulges to x = -10. Extents: 82 x 20 x 18 in."""
    b = Builder()
    b.add(314, [60.0, 60.0, 60.0], status="00000200")
    lines = []
    x0, x1, y1, z1 = 0.0, 72.0, 20.0, 8.0
    rect = [(x0, 0.0), (x1, 0.0), (x1, y1), (x0, y1)]
    for z in (0.0, z1):
        lines += [b.add(110, [*rect[i], z, *rect[(i + 1) % 4], z]) for i in range(4)]
    lines += [b.add(110, [x, y, 0.0, x, y, z1]) for x, y in rect]
    lines += [b.add(110, [x, 0.0, z1, x, y1, z1]) for x in (12.0, 24.0, 48.0, 60.0)]   # cross members
    # the arch: local XY plane onto world YZ (local x -> y, y -> z, z -> x), at x = 36, z = 8
    arch = b.add(124, [0, 0, 1, 36.0, 1, 0, 0, 0.0, 0, 1, 0, 8.0])
    lift = b.add(124, rotation_z(0, (0.0, 0.0, 8.0)))
    arcs = [b.add(100, [0.0, 10.0, 0.0, 20.0, 0.0, 0.0, 0.0], matrix=arch),    # upper half, ccw
            b.add(100, [0.0, 0.0, 10.0, 0.0, 20.0, 0.0, 0.0], matrix=lift)]    # left half, ccw
    b.add(402, [len(lines), *lines], form=15)
    b.add(402, [len(arcs), *arcs], form=15)
    return iges_text(b.entities, start="valterm test sample: a wireframe frame in inches",
                     units_flag=1, units_name="2HIN", declare=True, scale="1.",
                     names=holl("valterm tests"), stamp=holl("260101.000000"))


def arcs_sample() -> str:
    """Curves in z = 0, millimetres: a 100 arc (r 25, a quarter turned 90 degrees about Z to
    x 75..100, y 0..25), a 104 half ellipse (40 x 20, shifted to x -40..40, y 60..80) and a
    rational 126 quarter circle (r 10, x 200..210, y 0..10). Extents: 250 x 80, flat."""
    b = Builder()
    turn = b.add(124, rotation_z(90, (100.0, 0.0, 0.0)))
    shift = b.add(124, rotation_z(0, (0.0, 60.0, 0.0)))
    arc = b.add(100, [0.0, 0.0, 0.0, 25.0, 0.0, 0.0, 25.0], matrix=turn, status=OCCT_STATUS["curve"])
    ellipse = b.add(104, [1.0, 0.0, 4.0, 0.0, 0.0, -1600.0, 0.0, 40.0, 0.0, -40.0, 0.0], form=1,
                    matrix=shift, status=OCCT_STATUS["curve"])
    w = math.sqrt(0.5)
    spline = b.add(126, [2, 2, 1, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1.0, w, 1.0,
                         210.0, 0.0, 0.0, 210.0, 10.0, 0.0, 200.0, 10.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0],
                   status=OCCT_STATUS["curve"])
    b.add(402, [3, arc, ellipse, spline], form=1)
    return iges_text(b.entities, start="valterm test sample: arcs, an ellipse and a spline",
                     scale="1.", names=holl("valterm tests"), stamp=holl("20260101.000000"))


def points_sample() -> str:
    """Four 116 points of a 0.5 m x 0.25 m rectangle in z = 0, in METRES (units flag 6 with
    the units name left empty), and a 322 attribute table definition."""
    b = Builder()
    for x, y in ((0.0, 0.0), (0.5, 0.0), (0.5, 0.25), (0.0, 0.25)):
        b.add(116, [x, y, 0.0, 0], status="00000001")
    b.add(322, [holl("NODES"), 1, 1, 1, 1, 1], form=1, status="00000201")
    return iges_text(b.entities, start="valterm test sample: four points in metres",
                     units_flag=6, units_name="", declare=True, scale="1.0",
                     names=holl("valterm tests"), stamp=holl("000101.000000"))


# file name -> (writer, the shared sample of the same kind)
SAMPLES = {
    "valterm-box-60mm.iges": (box_sample, "occt-box-100mm.iges"),
    "valterm-wireframe-inches.igs": (wireframe_sample, "solidworks-chassis-wireframe.igs"),
    "valterm-arcs.iges": (arcs_sample, "occt-arcs.iges"),
    "valterm-points-metres.igs": (points_sample, "ansys-points.igs"),
}



@dataclass(frozen=True)
class Sample:
    """An IGES file and the facts the tests check about it (None: not pinned)."""

    path: Path
    units: str                                      # what the header says: MM, IN or M
    size_mm: tuple[float | None, ...]
    model_box: tuple[tuple[float, ...], tuple[float, ...]] | None = None  # model-space min, max (mm)

    @property
    def id(self) -> str:
        return self.path.name


MM_PER_IN = 25.4
# the project's samples: facts from the geometry written above, worked out by hand
OURS = {
    "box": Sample(DATA / "valterm-box-60mm.iges", "MM", (60.0, 60.0, 60.0), ((-20, -10, 0), (40, 50, 60))),
    "wireframe": Sample(DATA / "valterm-wireframe-inches.igs", "IN",
                        (82 * MM_PER_IN, 20 * MM_PER_IN, 18 * MM_PER_IN)),
    "arcs": Sample(DATA / "valterm-arcs.iges", "MM", (250.0, 80.0, 1.0)),
    "points": Sample(DATA / "valterm-points-metres.igs", "M", (500.0, 250.0, 1.0)),
}
# the CAD-written files, when present: facts read off them (the chassis pinned by hand, x only)
THEIRS = {
    "box": Sample(SHARED / "occt-box-100mm.iges", "MM", (100.0, 100.0, 100.0), ((-50,) * 3, (50,) * 3)),
    "wireframe": Sample(SHARED / "solidworks-chassis-wireframe.igs", "IN",
                        ((10.3236 + 63.2043) * MM_PER_IN, None, None)),
    "arcs": Sample(SHARED / "occt-arcs.iges", "MM", (313.03, 281.94, 1.0)),
    "points": Sample(SHARED / "ansys-points.igs", "M", (1000.0, 1000.0, 1.0)),
}


def samples(kind: str) -> list[Sample]:
    """The project's sample of a kind, and the CAD-written one as well when it is beside us."""
    return [OURS[kind]] + ([THEIRS[kind]] if THEIRS[kind].path.is_file() else [])


def of_kind(kind: str) -> pytest.MarkDecorator:
    """Parametrize a test's `sample` over `samples(kind)`."""
    return pytest.mark.parametrize("sample", samples(kind), ids=lambda s: s.id)


def every_sample() -> list[Sample]:
    return [s for kind in OURS for s in samples(kind)]


def write_samples(folder: Path = DATA) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for name, (writer, _) in SAMPLES.items():
        path = folder / name
        path.write_bytes(writer().encode("ascii"))
        written.append(path)
    return written


if __name__ == "__main__":
    for written in write_samples():
        print(written)
