"""Location files, NAME.LOC (§7.3, Figs. 7-3 and C-21).

One location a line: ``POINT A, 465., -45., -245., 89., 91., 0.`` -- the word POINT, a
space, a name of up to 9 characters, then X Y Z (mm) and O A T (degrees), separated by
commas (spaces are accepted too). Blank lines and ``;`` comment lines are skipped.

V+ programs (issue 14) add two kinds of line: a dotted name of up to 15 characters
(``POINT pick.1, ...``), and a precision point, six joint angles in degrees
(``POINT #SAFE, 0, -90, 90, 0, 0, 0``). ``read_locations`` returns the locations only;
``read_location_file`` returns the precision points too.

A location taught by HERE or the pendant keeps its configuration and joint angles (SPEC §3a):
its line may end with the three configuration words and the six angles,
``POINT P2, 400.00, 0.00, 0.00, 90.00, 90.00, 0.00, LEFTY ABOVE NOFLIP, 10.00, ...`` (STOREL
writes them; files without them are read as before).
A file whose comment line says ``; ANGLES YAW PITCH ROLL`` holds V+'s angles (issue 23:
Z-Y-Z yaw, pitch, roll, ``core/transform.py``) instead of O A T; it is read as the same
poses (every Location keeps O A T) and ``format_locations(..., YPR)`` writes one.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from valterm.core.errors import ValtermError
from valterm.core.files._text import (
    check_line_lengths,
    numbered_lines,
    parse_number,
    read_text,
    split_fields,
)
from valterm.core.files.atomic import write_text_atomic
from valterm.core.files.errors import BadName, FileFormatError, FileWriteError, shown_name
from valterm.core.files.limits import MAX_FILE_BYTES, MAX_LOCATIONS
from valterm.core.kinematics import Config, Location
from valterm.core.transform import convert_orientation

# A location name: a letter then up to 8 letters or digits (§7.3: "up to 9 characters").
LOCATION_NAME = re.compile(r"[A-Z][A-Z0-9]{0,8}")

# A V+ name (the V+ reference: a letter, then letters, digits, '_' or '.', at most 15 characters)
# and a precision point name (#name).
VPLUS_LOCATION_NAME = re.compile(r"[A-Z][A-Z0-9_.]{0,14}")
PRECISION_NAME = re.compile(r"#[A-Z][A-Z0-9_.]{0,14}")
MAX_VPLUS_NAME = 15
RULE_1985 = "a letter then up to 8 letters or digits (the 1985 rule, §7.3)"
RULE_VPLUS = "a letter then letters, digits, '_' or '.', at most 15 characters (V+'s rule)"

_POINT = re.compile(r"POINT(?![A-Z0-9])[\s,]*(.*)", re.IGNORECASE)

_FIELDS = ("X", "Y", "Z", "O", "A", "T")
VPLUS_ANGLES = "; ANGLES YAW PITCH ROLL"  # the comment line of a file in V+'s convention
_VPLUS_ANGLES = re.compile(r"^\s*;\s*ANGLES\s+YAW\s+PITCH\s+ROLL\s*$", re.IGNORECASE | re.MULTILINE)


def check_location_name(name: str) -> str:
    """The name upper-cased, or BadName saying why it is not a location name."""
    upper = name.strip().upper()
    if not LOCATION_NAME.fullmatch(upper):
        raise BadName(
            f"{shown_name(name)!r} is not a location name: {RULE_1985}"
        )
    return upper


def _file_name(text: str) -> str:
    """A name as a location file may hold it: a V+ name (every 1985 name is one too), or a
    #precision point; BadName stating both rules."""
    upper = text.strip().upper()
    if PRECISION_NAME.fullmatch(upper) or VPLUS_LOCATION_NAME.fullmatch(upper):
        return upper
    point = "# then " if upper.startswith("#") else ""
    raise BadName(f"{shown_name(text)!r} is not a location name: {point}{RULE_VPLUS}; "
                  f"a 1985 program's: {RULE_1985}")


def read_locations(path: str | Path) -> dict[str, Location]:
    """Read a location file (FileFormatError if malformed)."""
    path = Path(path)
    return parse_locations(read_text(path, "location"), path)


def read_location_file(path: str | Path) -> tuple[dict[str, Location], dict[str, tuple[float, ...]]]:
    """The locations and the precision points (#name: six joint angles) of a location file."""
    path = Path(path)
    points: dict[str, tuple[float, ...]] = {}
    return parse_locations(read_text(path, "location"), path, points), points


def parse_locations(text: str, name: str | Path,
                    points: dict[str, tuple[float, ...]] | None = None) -> dict[str, Location]:
    """Parse location-file text into {NAME: Location}; a later line with the same name wins.

    A file of only comments holds no locations; a file with nothing at all is damaged.
    Precision points go to ``points`` when given (skipped otherwise).
    """
    where = Path(name)
    if not text.strip():
        raise FileFormatError(where, 0, "the location file is empty (no POINT lines)")
    check_line_lengths(text, where, "location")
    found: dict[str, Location] = {}
    for number, line in numbered_lines(text):
        stripped = line.strip()
        if not stripped or stripped.startswith(";"):
            continue
        match = _POINT.match(stripped)
        if match is None:
            raise FileFormatError(where, number, f"expected 'POINT name, X, Y, Z, O, A, T', not {_shorten(stripped)!r}")
        fields = split_fields(match.group(1))
        if not fields:
            raise FileFormatError(where, number, "POINT without a location name")
        try:
            point = _file_name(fields[0])
        except ValueError as error:
            raise FileFormatError(where, number, str(error)) from None
        values = fields[1:]
        if point.startswith("#"):
            if len(values) != 6:
                raise FileFormatError(where, number,
                                      f"POINT {point}: expected 6 numbers (JT1..JT6), found {len(values)}")
            angles = tuple(parse_number(v, where, number, f"POINT {point} JT{i}") for i, v in enumerate(values, 1))
            if points is not None:
                points[point] = angles
            continue
        if point not in found and len(found) >= MAX_LOCATIONS:
            raise FileFormatError(where, number, f"more than {MAX_LOCATIONS} locations in one file")
        found[point] = _location(point, values, where, number)
    if _VPLUS_ANGLES.search(text):  # yaw pitch roll: the same poses, kept as O A T
        found = {name: location._replace(oat=convert_orientation(location.oat, "YPR", "OAT"))
                 for name, location in found.items()}
    return found


def _location(point: str, values: list[str], where: Path, number: int) -> Location:
    """X Y Z O A T, then optionally the configuration (three words) and the six joint angles."""
    if len(values) not in (6, 9, 15):
        raise FileFormatError(
            where, number, f"POINT {point}: expected 6 numbers (X, Y, Z, O, A, T), "
            f"optionally then 3 configuration words and 6 joint angles; found {len(values)} fields"
        )
    numbers = [parse_number(v, where, number, f"POINT {point} {axis}") for v, axis in zip(values, _FIELDS)]
    config = _config(point, values[6:9], where, number) if len(values) > 6 else None
    joints = tuple(parse_number(v, where, number, f"POINT {point} JT{i}")
                   for i, v in enumerate(values[9:], 1)) if len(values) == 15 else None
    return Location((numbers[0], numbers[1], numbers[2]), (numbers[3], numbers[4], numbers[5]), config, joints)


def _config(point: str, words: list[str], where: Path, number: int) -> Config:
    """The three configuration words of a POINT line (three words, none twice: each indicator once)."""
    try:
        return Config.parse(" ".join(words))
    except ValtermError as error:
        raise FileFormatError(where, number, f"POINT {point}: {error} (e.g. LEFTY ABOVE NOFLIP)") from None


def format_locations(locations: dict[str, Location],
                     points: dict[str, tuple[float, ...]] | None = None, convention: str = "OAT") -> str:
    """Location-file text, one ``POINT`` line per location (with its configuration and joints
    when it keeps them), in the order given; then the precision points (#name) if any.
    The thesis's numbers (Figs. 7-3, C-21): X Y Z O A T to 2 decimals; joint angles with
    enough digits that the pose they make reads back within 0.01 mm (``format_joint``).
    ``convention`` "YPR" writes V+'s yaw pitch roll (the file says so on its first line)."""
    lines = [VPLUS_ANGLES] if convention == "YPR" else []
    for name, location in locations.items():
        point = _file_name(name)
        angles = convert_orientation(location.oat, "OAT", "YPR") if convention == "YPR" else location.oat
        numbers = ", ".join(format_coordinate(v) for v in (*location.xyz, *angles))
        if location.config is not None:
            numbers += ", " + " ".join(location.config.words)
            if location.joints is not None:
                numbers += ", " + ", ".join(format_joint(v) for v in location.joints)
        lines.append(f"POINT {point}, {numbers}")
    for name, joints in (points or {}).items():
        lines.append(f"POINT {_file_name(name)}, " + ", ".join(format_joint(v) for v in joints))
    if not lines:
        lines.append("; NO LOCATIONS")  # an empty file reads as damaged, so say it is empty
    return "\n".join(lines) + "\n"


# A joint angle's decimals: 0.000005 degrees at most off, times a PUMA's reach (under 1.5 m)
# and six joints, moves the tool under 0.001 mm; the thesis's 2 decimals (0.005 degrees)
# could move it 0.1 mm.
JOINT_DECIMALS = 5


def format_coordinate(value: float) -> str:
    """X, Y, Z (mm) or an orientation angle as the thesis's files write it: 2 decimals."""
    text = f"{float(value):.2f}"
    return "0.00" if float(text) == 0 else text  # no "-0.00"


def format_joint(value: float) -> str:
    """A joint angle: 2 decimals when they hold it exactly (``10.00``), else up to
    JOINT_DECIMALS, trailing zeros dropped."""
    text = f"{float(value):.{JOINT_DECIMALS}f}".rstrip("0")
    whole, _, decimals = text.partition(".")
    text = f"{whole}.{decimals:0<2}"
    return "0.00" if float(text) == 0 else text


def checked_location_text(path: str | Path, locations: dict[str, Location],
                          points: dict[str, tuple[float, ...]] | None = None) -> str:
    """The text ``write_locations`` would write, checked as the reader will check it: more
    locations than a file may hold, or anything ``read_location_file`` would refuse, is a
    FileWriteError (nothing written) instead of a file the simulator cannot read back."""
    where = Path(path)
    if len(locations) > MAX_LOCATIONS:
        raise FileWriteError(where, f"{len(locations)} locations are more than one location file "
                                    f"holds ({MAX_LOCATIONS}); nothing written")
    text = format_locations(locations, points)
    if len(text.encode()) > MAX_FILE_BYTES:
        raise FileWriteError(where, f"the locations would make a file larger than {MAX_FILE_BYTES} bytes, "
                                    "the most a location file may hold; nothing written")
    try:
        parse_locations(text, where, {})
    except FileFormatError as error:
        raise FileWriteError(where, f"the simulator could not read it back ({error}); nothing written") from None
    return text


def write_locations(path: str | Path, locations: dict[str, Location],
                    points: dict[str, tuple[float, ...]] | None = None, expected: str | None = None) -> str:
    """Write the locations (and precision points) atomically; returns the text written.
    FileWriteError for a set the reader would refuse; with ``expected`` (the file's stamp as
    this session knew it, "" for none) FileChanged, nothing written, when it differs now."""
    text = checked_location_text(path, locations, points)
    write_text_atomic(path, text, expected=expected)
    return text


# a file's modification time (ns) and size: STOREL tells a file another session stored since
FileState = tuple[int, int]


def file_state(path: Path) -> FileState | None:
    """What ``at_start`` keeps of a file (None: there is none)."""
    try:
        info = path.stat()
    except OSError:
        return None
    return info.st_mtime_ns, info.st_size


def location_files_now(folder: Path) -> dict[str, FileState]:
    """The state of every .LOC file of ``folder`` (a stat each: no file is read)."""
    try:
        names = [entry for entry in os.scandir(folder) if entry.name.upper().endswith(".LOC")]
    except OSError:
        return {}
    found = {entry.name.upper(): file_state(Path(entry.path)) for entry in names}
    return {name: state for name, state in found.items() if state is not None}


def _shorten(text: str, limit: int = 40) -> str:
    return text if len(text) <= limit else text[: limit - 3] + "..."
