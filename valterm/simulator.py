"""The simulated robot and its cell: state plus actions that yield events.

Every action is a generator of ``valterm.events`` objects (each pose of a motion, each
message). A refused motion raises ``MotionRefused`` before yielding any pose, so nothing
moves. The interpreter, the app and the tests all drive this one class.
"""
from __future__ import annotations
# (implementation in progress: see the method docstrings for the contract)
