"""valterm: a terminal recreation of the 1985 Lehigh VAL-II SIMULATOR.

The simulator core (kinematics, motion, the work cell, collision, files and the
VAL-II interpreter) imports neither textual nor rich; the app in ``valterm.ui``
is a thin layer of screens over it.
"""

__version__ = "0.1.0"


def version() -> str:
    """The installed distribution's version; ``__version__`` when run from a bare checkout."""
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as installed

    try:
        return installed("valterm")
    except PackageNotFoundError:
        return __version__
