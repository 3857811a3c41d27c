"""The readouts: the clamp position of Fig. 2-8 and the part position of Fig. 4-2.

The ``format_*`` functions are plain text (the hardcopy and the tests use them too); the
widgets show them.
"""

from __future__ import annotations

from typing import Sequence

from textual.widgets import Static

from valterm.core.events import Where

SCS_H = 26.0  # SPEC §1: Y_s = Z_w + H
LABEL = 8
COLUMN = 9


def _row(label: str, cells: Sequence[str]) -> str:
    return label.ljust(LABEL) + "".join(c.rjust(COLUMN) for c in cells)


def _num(value: float) -> str:
    text = f"{value:.2f}"
    return "0.00" if text == "-0.00" else text


def format_where(where: Where) -> list[str]:
    """Fig. 2-8: clamp status, XW YW ZW O A T, the indicators, JT1..JT6 (four lines)."""
    config = where.config
    return [
        _row(where.clamp, ("XW", "YW", "ZW", "O", "A", "T")),
        _row(config.get("arm", ""), [_num(v) for v in (*where.xyz, *where.oat)]),
        _row(config.get("elbow", ""), [f"JT {i}" for i in range(1, 7)]),
        _row(config.get("wrist", ""), [_num(v) for v in where.joints]),
    ]


def world_to_screen(xyz: Sequence[float]) -> tuple[float, float, float]:
    """SCS of a world point: X_s = Y_w, Y_s = Z_w + 26, Z_s = X_w."""
    x, y, z = (float(v) for v in xyz)
    return y, z + SCS_H, x


def format_part(number: int, reference: Sequence[float]) -> list[str]:
    """Fig. 4-2: the part's reference corner in world and in screen coordinates."""
    head = 32
    world = [_num(v) for v in reference]
    screen = [_num(v) for v in world_to_screen(reference)]
    return [
        f"WORLD COORDINATES FOR PART NO. {number}".ljust(head) + "".join(c.rjust(COLUMN) for c in ("XW", "YW", "ZW")),
        " " * head + "".join(c.rjust(COLUMN) for c in world),
        f"SCREEN COORDINATES FOR PART NO. {number}".ljust(head) + "".join(c.rjust(COLUMN) for c in ("X", "Y", "Z")),
        " " * head + "".join(c.rjust(COLUMN) for c in screen),
    ]


class PositionReadout(Static):
    """Fig. 2-8, kept current by the screen after every pose."""

    DEFAULT_CSS = "PositionReadout { height: auto; }"

    def show_where(self, where: Where, extra: str = "") -> None:
        lines = format_where(where)
        if extra:
            lines.append(extra)
        self.update("\n".join(lines))


class PartReadout(Static):
    """Fig. 4-2, kept current while a part is repositioned."""

    DEFAULT_CSS = "PartReadout { height: auto; }"

    def show_part(self, number: int, reference: Sequence[float]) -> None:
        self.update("\n".join(format_part(number, reference)))
