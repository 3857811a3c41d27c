"""The picture's legend: its colour indices, one list for the raster, the overlays and the
widget that maps them to terminal colours (0 is an empty cell), and how much of the clamp's
path the trace keeps. Without numpy: the app's first frame is drawn before the picture's
modules load (issue 25, the start)."""

from __future__ import annotations

AXES_COLOUR = 1
LED_COLOUR = 2
HIGHLIGHT_COLOUR = 3  # e.g. a part in collision
TRACE_COLOUR = 4
GHOST_COLOUR = 5
SEEN_COLOUR = 6  # the part the LED sensor sees
LINK_COLOUR_BASE = 8  # robot links 0..7 -> 8..15
OBJECT_COLOUR_BASE = 16  # objects 1..n -> 16..31 (cycling)
N_OBJECT_COLOURS = 16
DIM_OFFSET = 64  # colour + DIM_OFFSET: the same colour, dimmer (further from the viewer)

TRACE_POINTS = 4000  # clamp positions kept by the trace (and poses the player keeps for it)
