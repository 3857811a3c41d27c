"""``valterm demo [--speed X]``: the example session of Tables C-1..C-3 (and CONV1) replayed
key by key, in a loop, for museum use; any key hands control to the visitor and an idle
minute restarts the demo. The key script is data, valterm/data/DEMO.KEYS; this module reads it
(no UI import) and starts the demo app.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

from valterm.core import resources

DEMO_FILE = resources.data_path("DEMO.KEYS")

# Named keys of the script -> Textual key names.
NAMED_KEYS = {"RETURN": "enter", "TAB": "tab", "ESC": "escape", "SPACE": "space", "CTRL-C": "ctrl+c"}


@dataclass(frozen=True)
class DemoItem:
    """One item of the script: kind key | text | pause | caption; ``replay_only`` for % items."""

    kind: str
    value: str
    line: int
    replay_only: bool = False

    @property
    def seconds(self) -> float:
        return float(self.value) if self.kind == "pause" else 0.0

    def keys(self) -> list[str]:
        """The Textual key names this item presses."""
        if self.kind == "key":
            return [NAMED_KEYS.get(self.value, self.value.lower() if self.value.isalpha() else self.value)]
        if self.kind == "text":
            return ["space" if c == " " else c for c in self.value]
        return []


class DemoScriptError(ValueError):
    pass


def parse_demo(text: str) -> list[DemoItem]:
    items: list[DemoItem] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith(";"):
            continue
        replay_only = line.startswith("%")
        if replay_only:
            line = line[1:].strip()
        if line.startswith("@"):
            items.append(DemoItem("caption", line[1:].strip(), number, replay_only))
        elif line.startswith('"'):
            if len(line) < 2 or not line.endswith('"'):
                raise DemoScriptError(f"DEMO.KEYS line {number}: a typed text ends with a quote")
            items.append(DemoItem("text", line[1:-1], number, replay_only))
        elif line.upper().startswith("PAUSE"):
            try:
                seconds = float(line[5:].strip() or "1")
            except ValueError:
                raise DemoScriptError(f"DEMO.KEYS line {number}: PAUSE takes seconds") from None
            items.append(DemoItem("pause", str(seconds), number, replay_only))
        elif line.upper() in NAMED_KEYS or len(line) == 1:
            items.append(DemoItem("key", line.upper() if len(line) > 1 else line, number, replay_only))
        else:
            raise DemoScriptError(f"DEMO.KEYS line {number}: {line!r} is not a key, \"text\", PAUSE n or @ caption")
    return items


def load_demo(path: str | Path = DEMO_FILE) -> list[DemoItem]:
    return parse_demo(Path(path).read_text(encoding="utf-8"))


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = sub.add_parser("demo", help="replay the thesis's example session in a loop (museum mode)")
    parser.add_argument("--speed", type=float, default=1.0, help="faster (2) or slower (0.5) than the default pace")
    parser.add_argument("--once", action="store_true", help="play the script once, then hand over")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from valterm.ui.screens.demo import run_demo

    if not args.speed > 0:
        print("valterm demo: --speed must be positive")
        return 2
    return run_demo(speed=args.speed, once=args.once, workspace=getattr(args, "workspace", None))
