"""The one error base class of the core.

Every error the core raises on purpose (a malformed file, a refused name, an unreachable
location, a VAL-II statement it cannot run) is a ``ValtermError``; the app and the command
line catch that and show its message. Anything else that escapes is a bug: the edges log
it with its traceback and say so in one line.
"""

from __future__ import annotations


class ValtermError(Exception):
    """A refusal the user can act on; ``str(error)`` is the message to show."""


class RefusedValue(ValtermError, ValueError):
    """A value the user gave (an argument, a typed word, a name) that is refused: a
    ValtermError the edges show, and a ValueError where a parse is expected to fail."""
