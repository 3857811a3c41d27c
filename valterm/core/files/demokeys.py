"""DEMO.KEYS: the key script of the museum demo (the example session of App. C, key by key).

One item a line: a key (``E``, ``RETURN``), a typed text (``"DEMO3.SET"``), ``PAUSE n``,
``@ caption`` for the visitor, ``= TEXT`` a claim of the caption above it (its stage prints a
line holding TEXT: tests/test_demo_captions.py plays each stage and checks), and ``%`` before
an item of the full replay only. The script is data the demo app plays and the replay test
checks; it is read here, with no UI import.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from valterm.core import resources
from valterm.core.files._text import read_text
from valterm.core.files.errors import FileFormatError

DEMO_NAME = "DEMO.KEYS"

# Named keys of the script -> the key names the app's key events use.
NAMED_KEYS = {"RETURN": "enter", "TAB": "tab", "ESC": "escape", "SPACE": "space", "CTRL-C": "ctrl+c"}

KINDS = ("key", "text", "pause", "caption", "claim")


class DemoScriptError(FileFormatError):
    """A line of a key script that is not a key, a text, a PAUSE or a caption."""


@dataclass(frozen=True)
class DemoItem:
    """One item of the script: ``kind`` is key | text | pause | caption | claim; ``replay_only``
    for % items."""

    kind: str
    value: str
    line: int
    replay_only: bool = False

    @property
    def seconds(self) -> float:
        return float(self.value) if self.kind == "pause" else 0.0

    def keys(self) -> list[str]:
        """The key names this item presses (letters as typed, named keys by their name)."""
        if self.kind == "key":
            return [NAMED_KEYS.get(self.value, self.value.lower() if self.value.isalpha() else self.value)]
        if self.kind == "text":
            return ["space" if c == " " else c for c in self.value]
        return []


def _item(line: str, number: int, replay_only: bool, path: str | Path) -> DemoItem:
    if line.startswith("@"):
        return DemoItem("caption", line[1:].strip(), number, replay_only)
    if line.startswith("=") and line[1:].strip():
        return DemoItem("claim", line[1:].strip().upper(), number, replay_only)
    if line.startswith('"'):
        if len(line) < 2 or not line.endswith('"'):
            raise DemoScriptError(path, number, "a typed text ends with a quote")
        return DemoItem("text", line[1:-1], number, replay_only)
    if line.upper().startswith("PAUSE"):
        try:
            seconds = float(line[5:].strip() or "1")
        except ValueError:
            raise DemoScriptError(path, number, "PAUSE takes seconds") from None
        if not 0 <= seconds <= 600:
            raise DemoScriptError(path, number, "PAUSE takes 0 to 600 seconds")
        return DemoItem("pause", str(seconds), number, replay_only)
    if line.upper() in NAMED_KEYS or len(line) == 1:
        return DemoItem("key", line.upper() if len(line) > 1 else line, number, replay_only)
    raise DemoScriptError(path, number, f'{line!r} is not a key, "text", PAUSE n, @ caption or = claim')


def parse_demo(text: str, path: str | Path = DEMO_NAME) -> list[DemoItem]:
    """The items of a key script; ``path`` names it in messages (``DEMO.KEYS:12: reason``)."""
    items: list[DemoItem] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith(";"):
            continue
        replay_only = line.startswith("%")
        if replay_only:
            line = line[1:].strip()
        items.append(_item(line, number, replay_only, path))
    if not any(item.kind in ("key", "text") and not item.replay_only for item in items):
        raise DemoScriptError(path, 0, "the script presses no key")
    return items


def load_demo(path: str | Path | None = None) -> list[DemoItem]:
    """The bundled DEMO.KEYS, or the script at ``path``."""
    if path is None:
        return parse_demo(resources.read_text(DEMO_NAME))
    try:
        text = read_text(path, "key script")  # the one read path: a FIFO or a device is refused
    except FileFormatError as error:
        raise DemoScriptError(path, error.line, error.reason) from None
    return parse_demo(text, path)
