"""The user's keymap file: bindings rebound by their id, as posting's keymap does.

``$VALTERM_KEYMAP``, else ``$XDG_CONFIG_HOME/valterm/keymap.toml`` (``~/.config/...``).
One line a binding, its id (docs/KEYBOARD.md lists them all) and the keys, comma-separated,
in Textual's names::

    # valterm keymap
    "main.pendant" = "j"            # J opens PENDANT MODE instead of P
    "view.model" = "f12,ctrl+m"     # the model alone: F12 or CTRL-M instead of F8

An optional ``[keymap]`` table holds the same lines. A missing default file is no keymap;
a bad one is a FileProblem naming the line.
"""

from __future__ import annotations

import os
import tomllib
from collections.abc import Collection
from pathlib import Path

from valterm.core.files._text import read_text
from valterm.core.files.errors import FileFormatError, FileProblem

KEYMAP_ENV = "VALTERM_KEYMAP"
MAX_KEYMAP_BYTES = 256 * 1024  # a line a binding: a few KB; far more is no keymap


def keymap_path() -> Path:
    """Where the keymap file is looked for."""
    chosen = os.environ.get(KEYMAP_ENV)
    if chosen:
        return Path(chosen).expanduser()
    config = os.environ.get("XDG_CONFIG_HOME") or str(Path("~/.config").expanduser())
    return Path(config) / "valterm" / "keymap.toml"


def read_keymap(path: Path | None = None, known: Collection[str] = ()) -> dict[str, str]:
    """{binding id: keys} of the file (``known``: the ids there are, when given)."""
    chosen = path is not None or bool(os.environ.get(KEYMAP_ENV))
    path = path if path is not None else keymap_path()
    if not chosen and not os.path.lexists(path):
        return {}  # no keymap: the default bindings
    if not os.path.lexists(path):
        raise FileProblem(path, "the keymap file does not exist")
    # the one read path: a FIFO or a device (/dev/zero) is refused at once, the size capped
    text = read_text(path, "keymap", MAX_KEYMAP_BYTES)
    try:
        table = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise FileFormatError(path, getattr(error, "lineno", 0) or _line_of(str(error)),
                              "not a keymap: write \"binding.id\" = \"keys\"") from None
    table = table.get("keymap", table) if isinstance(table.get("keymap"), dict) else table
    keymap: dict[str, str] = {}
    for binding_id, keys in table.items():
        line = _line_with(text, binding_id)
        if not isinstance(keys, str) or not keys.strip():
            raise FileFormatError(path, line, f"{binding_id}: the keys must be a text such as \"f12\"")
        if known and binding_id not in known:
            raise FileFormatError(path, line, f"{binding_id} is no binding id (docs/KEYBOARD.md lists them)")
        keymap[binding_id] = ",".join(key.strip() for key in keys.split(","))
    return keymap


def _line_with(text: str, binding_id: str) -> int:
    for number, line in enumerate(text.splitlines(), start=1):
        if binding_id in line:
            return number
    return 0


def _line_of(message: str) -> int:
    """tomllib's "(at line 3, column 5)"."""
    marker = "at line "
    if marker not in message:
        return 0
    digits = message.split(marker, 1)[1].split(",", 1)[0].strip(") ")
    return int(digits) if digits.isdigit() else 0
