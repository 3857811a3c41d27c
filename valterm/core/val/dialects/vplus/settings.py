"""V+ settings and readouts: SPEED, PARAMETER, HERE, DECOMPOSE, TOOL, TYPE, TIMER,
ENABLE/DISABLE, WHERE, STATUS.
"""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np

from valterm.core.events import Message, TypeOut, Where
from valterm.core.transform import convert_orientation
from valterm.core.val import builders as shared
from valterm.core.val.builders import Build, Builder
from valterm.core.val.dialects.vplus.compiled import (
    controller_of,
    location_of,
    number_of,
    precision_of,
    store_location,
)
from valterm.core.val.dialects.vplus.expr import (
    NAME,
    array_key,
    compile_location,
    output_list,
    render_output,
)
from valterm.core.val.dialects.vplus.statements import split_top
from valterm.core.val.machine import signal_line
from valterm.core.val.ops import (
    Events,
    Op,
)
from valterm.core.val.parser import (
    Statement,
)
from valterm.core.val.typeout import NO_LINE_END

_N = NAME

def _speed(c: Build, st: Statement) -> Op:
    speed, always, per_unit = number_of(c, st.args[0]), bool(st.args[1]), float(st.args[2])

    def run() -> Events:
        wanted = float(speed(c.variables)) * (per_unit or 1.0)
        got = c.sim.set_program_speed(wanted, bool(per_unit), always)
        if got != wanted:
            range_said = "(10 TO 100)" if not per_unit else "MM/S (THE ROBOT'S TOOL SPEED)"
            yield Message(f"SPEED SET TO {shared.format_value(got)} {range_said}", "warning")
        return c.next
    return c.action(run)


def _parameter(c: Build, st: Statement) -> Op:
    name, value = st.args[0], number_of(c, st.args[1])
    machine = controller_of(c)

    def run() -> Events:
        machine.set_parameter(name, float(value(c.variables)))
        return c.next
        yield
    return c.action(run)


def _here(c: Build, st: Statement) -> Op:
    """HERE name, HERE loc[i] (an array element), HERE #point (the joints)."""
    name = st.args[0]
    machine = controller_of(c)
    element = re.fullmatch(rf"({_N})\s*\[(.+)\]", name)
    indexes = [number_of(c, i) for i in split_top(element.group(2))] if element is not None else []

    def run() -> Events:
        if element is not None:
            key = array_key(element.group(1), [i(c.variables) for i in indexes])
            store_location(c, key, compile_location("HERE", machine)(c.variables))
            return c.next
        if name.startswith("#"):
            machine.precision[name] = tuple(float(j) for j in c.sim.joints)
        else:
            store_location(c, name, compile_location("HERE", machine)(c.variables))
        return c.next
        yield
    return c.action(run)


def _decompose(c: Build, st: Statement) -> Op:
    """DECOMPOSE a[i] = loc: X Y Z yaw pitch roll; of a precision point (#p, #PPOINT): its joints."""
    name, start_text, location_text = st.args
    start, where = number_of(c, start_text), location_of(c, location_text)
    point = precision_of(c, location_text) if location_text.startswith("#") else None

    def run() -> Events:
        first = int(start(c.variables))
        values = point(c.variables) if point is not None else where(c.variables).decompose()
        for offset, value in enumerate(values):
            c.variables[array_key(name, [first + offset])] = round(value, 9)
        return c.next
        yield
    return c.action(run)


def _tool(c: Build, st: Statement) -> Op:
    where = location_of(c, st.args[0])
    machine = controller_of(c)

    def run() -> Events:
        tool = where(c.variables)
        machine.tool = None if abs(tool.matrix - np.eye(4)).max() < 1e-9 else tool  # TOOL NULL
        return c.next
        yield
    return c.action(run)


def _type(c: Build, st: Statement) -> Op:
    machine = controller_of(c)
    items = output_list(st.args[0], machine)
    open_line = any(fn is None and fmt == NO_LINE_END for _text, fn, fmt in items)  # TYPE ..., /S

    def run() -> Events:
        lines = (machine.typed + render_output(items, c.variables)).split("\n")
        machine.typed = lines.pop() if open_line else ""
        for line in lines:
            yield TypeOut(line)
        return c.next
    return c.action(run)


def _timer(c: Build, st: Statement) -> Op:
    number, value = number_of(c, st.args[0]), number_of(c, st.args[1])
    machine = controller_of(c)

    def run() -> Events:
        machine.set_timer(number(c.variables), float(value(c.variables)))
        return c.next
        yield
    return c.action(run)


def _switch(c: Build, st: Statement) -> Op:
    machine, on = controller_of(c), st.command == "ENABLE"

    def run() -> Events:
        for name in st.args:
            machine.switches[name] = on
        return c.next
        yield
    return c.action(run)


def vplus_where(where: Where) -> Where:
    """A WHERE readout in V+'s convention: the same pose, yaw pitch roll instead of O A T."""
    return replace(where, ypr=convert_orientation(where.oat, "OAT", "YPR"))


def _where(c: Build, st: Statement) -> Op:
    def run() -> Events:
        yield vplus_where(c.sim.where())
        return c.next
    return c.action(run)


def _status(c: Build, st: Statement) -> Op:
    machine = controller_of(c)

    def run() -> Events:
        yield c.status()
        yield TypeOut(signal_line(machine))
        return c.next
    return c.action(run)


SETTINGS: dict[str, Builder] = {
    "SPEED": _speed, "PARAMETER": _parameter, "HERE": _here, "DECOMPOSE": _decompose, "TOOL": _tool,
    "TYPE": _type, "TIMER": _timer, "ENABLE": _switch, "DISABLE": _switch, "STATUS": _status, "WHERE": _where,
}
