"""Monitor commands about the robot's state that outlive a session: STOREL and RULES.

``STOREL NAME`` writes every location variable (with the configuration and joint angles a
taught one keeps) and every precision point to NAME.LOC in the workspace (SPEC §3a);
``RULES`` shows or sets the joint-state rules (``RULES 1985``, ``RULES CONTROLLER``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Protocol

from valterm.core.errors import ValtermError
from valterm.core.events import Error, Event, Message, Status
from valterm.core.val.machine import Machine
from valterm.core.val.parser import Statement
from valterm.core.val.protocol import Simulator

# what STOREL calls: (file name, locations, precision points) -> the path written
StoreLocations = Callable[[str, dict, dict], Path]  # type: ignore[type-arg]


class Interpreter(Protocol):
    """What these commands read of the interpreter (no import of it: no circle)."""

    sim: Simulator
    machine: Machine
    store_locations: StoreLocations | None

    def status(self) -> Status: ...


def storel(interpreter: Interpreter, st: Statement) -> Iterator[Event]:
    """STOREL NAME: the locations to NAME.LOC (through the workspace's one safe write path)."""
    name = (st.args[0] or "").strip() if st.args else ""
    if not name:
        yield Error("", 0, "STOREL NEEDS A FILE NAME: STOREL NAME WRITES NAME.LOC")
        return
    store = interpreter.store_locations
    if store is None:
        yield Error("", 0, "STOREL: THERE IS NO WORKSPACE TO WRITE TO")
        return
    sim = interpreter.sim
    locations = dict(sim.locations)
    precision = dict(interpreter.machine.precision)
    try:
        path = store(name.removesuffix(".LOC").removesuffix(".loc"), locations, precision)
    except (OSError, ValtermError) as error:
        yield Error("", 0, f"STOREL: {error}")
        return
    mark = getattr(sim, "mark_locations_stored", None)
    if mark is not None:
        mark(locations)
    count = len(locations) + len(precision)
    yield Message(f"{count} LOCATION{'S' if count != 1 else ''} STORED IN {path.name}")


def rules(interpreter: Interpreter, st: Statement) -> Iterator[Event]:
    """RULES: which joint-state rules are in force; RULES 1985 / RULES CONTROLLER sets them."""
    word = (st.args[0] or "").strip() if st.args else ""
    sim = interpreter.sim
    if word:
        setter = getattr(sim, "set_rules", None)
        if setter is None:
            yield Error("", 0, "RULES: THIS SIMULATOR HAS ONE SET OF RULES")
            return
        try:
            setter(word)
        except ValtermError as error:
            yield Error("", 0, str(error).upper())
            return
    yield interpreter.status()
