"""The project's own IGES samples (tests/data/iges/valterm-*): written by tests/iges_writer.py,
byte for byte, and of the entity types and header fields of the CAD-written ../shared/iges-samples."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from iges_writer import OURS, SAMPLES, THEIRS, entity_tally, write_samples

# entity types tallied from the directory entries of the CAD-written files (kept here so the
# check runs without them; test_tally_of_the_cad_files re-counts them when they are present)
CAD_TYPES = {
    "box": {102, 108, 110, 142, 144, 402},
    "wireframe": {100, 110, 124, 314, 402},
    "arcs": {100, 104, 124, 126, 402},
    "points": {116, 322},
}
OURS_BY_NAME = {s.path.name: s.path for s in OURS.values()}
PRESENT = [kind for kind in OURS if THEIRS[kind].path.is_file()]


def global_fields(text: str) -> list[str]:
    """The Global section's fields, Hollerith strings unwrapped (an independent little reader)."""
    glob = "".join(line[:72] for line in text.splitlines() if line[72:73] == "G")
    pd, rd = (glob[2], glob[6]) if glob.startswith("1H") else (",", ";")
    fields, i, cur = [], 0, ""
    while i < len(glob):
        head = re.match(r"\s*(\d+)H", glob[i:])
        if head and not cur.strip():
            n = int(head.group(1))
            cur = glob[i + head.end():i + head.end() + n]
            i += head.end() + n
            continue
        if glob[i] in (pd, rd):
            fields.append(cur.strip())
            cur = ""
            if glob[i] == rd:
                break
        else:
            cur += glob[i]
        i += 1
    return fields


def header(text: str) -> tuple[bool, float, str, str]:
    """Delimiters declared?, model space scale (field 13), units flag and name (14, 15)."""
    fields = global_fields(text)
    first = next(line for line in text.splitlines() if line[72:73] == "G")
    return first.startswith("1H"), float(fields[12]), fields[13], fields[14]


def test_regenerating_gives_the_same_bytes(tmp_path: Path) -> None:
    for fresh in write_samples(tmp_path):
        kept = OURS_BY_NAME[fresh.name]
        assert fresh.read_bytes() == kept.read_bytes(), f"{kept.name}: run python tests/iges_writer.py"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(SAMPLES)


@pytest.mark.parametrize("kind", list(OURS))
def test_our_samples_hold_the_cad_files_entity_types(kind: str) -> None:
    tally = entity_tally(OURS[kind].path.read_text())
    assert set(tally) == CAD_TYPES[kind]
    lines = OURS[kind].path.read_text().splitlines()
    assert all(len(line) == 80 for line in lines)
    counts = {letter: sum(1 for line in lines if line[72] == letter) for letter in "SGDP"}
    assert lines[-1][:32] == "".join(f"{k}{n:>7}" for k, n in counts.items())   # the Terminate line
    for letter in "SGDPT":
        numbers = [int(line[73:]) for line in lines if line[72] == letter]
        assert numbers == list(range(1, len(numbers) + 1))


def test_our_samples_match_the_cad_files() -> None:
    """Same entity types, delimiters declared or not, scale, units flag and name as the CAD file of each kind."""
    if not PRESENT:
        pytest.skip(f"the CAD-written samples are not in {THEIRS['box'].path.parent}")
    for kind in PRESENT:
        theirs = THEIRS[kind].path.read_text()
        assert set(entity_tally(theirs)) == CAD_TYPES[kind], kind
        assert header(OURS[kind].path.read_text()) == header(theirs), kind
