"""valterm: a terminal recreation of the 1985 Lehigh VAL-II SIMULATOR.

The simulator core (kinematics, motion, the work cell, collision, files and the
VAL-II interpreter) imports neither textual nor rich; the app in ``valterm.ui``
is a thin layer of screens over it.
"""

__version__ = "0.1.0"
