"""The limits a user can rely on (docs/LIMITS.md): every one is checked with a located message.

They are far above anything the thesis's files need, and low enough that a damaged or
hostile file is refused before it can stall the terminal or exhaust memory.
"""

from __future__ import annotations

MAX_FILE_BYTES = 5 * 1024 * 1024   # largest setup, location, program or variables file
MAX_LINE = 255                     # longest line of any of them (characters, tabs expanded)
MAX_PARTS = 100                    # most objects in a setup file (the thesis's arrays held 30)
MAX_VERTICES = 256                 # most vertices of one object (N of its `1,N` line)
MAX_STEPS = 10_000                 # most steps in one program
MAX_LOCATIONS = 10_000             # most locations in one location file
MAX_VARIABLES = 10_000             # most variables in CHECK.DAT
