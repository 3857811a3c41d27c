"""V+ CALL and CALLS with arguments: parameters by reference or by value, AUTO variables
saved and restored around the call (recursion works).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TypeVar

from valterm.core.kinematics import Location
from valterm.core.transform import Transform
from valterm.core.val.builders import Build, Builder
from valterm.core.val.dialects.vplus.compiled import (
    controller_of,
    number_of,
)
from valterm.core.val.dialects.vplus.expr import (
    NAME,
    array_key,
    compile_location,
    compile_number,
    compile_string,
)
from valterm.core.val.expr import ExprError, Fn, Values
from valterm.core.val.machine import Machine, MachineError
from valterm.core.val.ops import (
    Call,
    CompiledProgram,
    Events,
    Op,
    ProgramError,
    Run,
    RunStop,
)
from valterm.core.val.parser import (
    Statement,
)

T = TypeVar("T")
_N = NAME

# -- CALL with arguments --------------------------------------------------------------------

@dataclass(frozen=True)
class Argument:
    """One CALL argument: its value now, and (by reference) where the result goes back."""

    kind: str  # N number, L location, S string, A array
    read: Callable[[], object]
    write_back: Callable[[object], None] | None = None


@dataclass(frozen=True, slots=True)
class VCall(Call):
    """CALL name(args): parameters and AUTO variables saved, bound, restored on return."""

    arguments: tuple[Callable[[], Argument], ...] = ()
    machine: Machine | None = field(default=None, repr=False)
    variables: dict[str, float] = field(default_factory=dict, repr=False)
    locations: dict[str, Location] = field(default_factory=dict, repr=False)

    def callee(self) -> str:
        return self.program

    def control(self, run: Run, call: Callable[[str], CompiledProgram]) -> Events:
        program = self.callee()
        sub = yield from self.called(run, call, program)
        parameters = list(sub.analysis.program.parameters)
        if len(self.arguments) > len(parameters):
            raise RunStop(f"CALL {program}: {len(self.arguments)} ARGUMENTS FOR "
                          f"{len(parameters)} PARAMETERS", run.program.name, self.step.step)
        values = [argument() for argument in self.arguments]  # in the caller's scope
        restore = self._bind(parameters, values, sub.analysis.autos)
        return run.enter(sub, self.next, restore)

    def _bind(self, parameters: list[str], values: list[Argument], autos: list[str]) -> Callable[[], None]:
        V, L = self.variables, self.locations
        strings = self.machine.strings if self.machine is not None else {}
        own = [p.removesuffix("[]") for p in parameters] + [a for a in autos if a not in parameters]
        saved = {name: (V.get(name), L.get(name), strings.get(name)) for name in own}
        saved_arrays = {name: {k: v for k, v in V.items() if k.startswith(name + "[")} for name in own}
        for name in own:
            V.pop(name, None)
            for key in saved_arrays[name]:
                V.pop(key, None)
        for name, argument in zip(parameters, values):
            name = name.removesuffix("[]")
            value = argument.read()
            if argument.kind == "N":
                if value is not None:  # an undefined variable passed to be set
                    V[name] = float(value)  # type: ignore[arg-type]
            elif argument.kind == "L":
                assert isinstance(value, Location)
                L[name] = value
            elif argument.kind == "S":
                if value is not None:  # an undefined string passed to be set
                    strings[name] = str(value)
            else:
                assert isinstance(value, dict)
                for index, element in value.items():
                    V[f"{name}[{index}]"] = element

        def restore() -> None:
            results: list[tuple[Argument, object]] = []
            for name, argument in zip(parameters, values):
                name = name.removesuffix("[]")
                if argument.write_back is None:
                    continue
                if argument.kind == "N":
                    results.append((argument, V.get(name)))
                elif argument.kind == "L":
                    results.append((argument, L.get(name)))
                elif argument.kind == "S":
                    results.append((argument, strings.get(name)))
                else:
                    prefix = name + "["
                    results.append((argument, {k[len(prefix):-1]: v for k, v in V.items() if k.startswith(prefix)}))
            for name in own:
                for key in [k for k in V if k.startswith(name + "[")]:
                    del V[key]
                V.update(saved_arrays[name])
                number, location, string = saved[name]
                _put(V, name, number)
                _put(L, name, location)
                _put(strings, name, string)
            for argument, result in results:
                if result is not None and argument.write_back is not None:
                    argument.write_back(result)
        return restore


@dataclass(frozen=True, slots=True)
class VCallS(VCall):
    """CALLS $name(args): CALL of the program whose name is the string's value as the step runs."""

    named: Callable[[Values], str] = field(default=lambda V: "", repr=False)

    def callee(self) -> str:
        name = self.named(self.variables).strip().upper()
        if not re.fullmatch(_N, name):
            raise RunStop(f"CALLS: {name!r} IS NOT A PROGRAM NAME", self.step.program, self.step.step)
        return name


def _put(store: dict[str, T], name: str, old: T | None) -> None:
    """Put back what a name held before a CALL (nothing: the name is removed)."""
    if old is None:
        store.pop(name, None)
    else:
        store[name] = old


def _argument(c: Build, text: str) -> Callable[[], Argument]:
    machine, V, L = controller_of(c), c.variables, c.sim.locations
    if text.endswith("[]"):
        name = text[:-2]
        prefix = name + "["

        def array() -> Argument:
            elements = {k[len(prefix):-1]: v for k, v in V.items() if k.startswith(prefix)}

            def back(result: object) -> None:
                assert isinstance(result, dict)
                V.update({f"{name}[{k}]": v for k, v in result.items()})
            return Argument("A", lambda: elements, back)
        return array
    if text.startswith(("$", '"')):
        value = compile_string(text, machine)
        element = re.fullmatch(rf"(\${_N})\s*\[([^\[\]]*)\]", text)  # $a[i], by reference too
        indexes = [number_of(c, i) for i in element.group(2).split(",")] if element else []
        named = text if re.fullmatch(rf"\${_N}", text) else None

        def string() -> Argument:
            where = array_key(element.group(1), [i(V) for i in indexes]) if element else named
            if where is None:
                return Argument("S", lambda: value(V))

            def back(result: object) -> None:
                machine.strings[where] = str(result)
            # by reference: a string not yet defined is passed to be set
            return Argument("S", lambda: machine.strings.get(where), back)
        return string
    plain = text if re.fullmatch(_N, text) else None
    number = _try_number(text, machine)
    location = _try_location(text, machine)

    element = re.fullmatch(rf"({_N})\s*\[([^\[\]]*)\]", text)
    indexes = [number_of(c, i) for i in element.group(2).split(",")] if element else []

    def argument() -> Argument:
        if plain is not None:  # by reference: a variable (perhaps not yet defined) or a location
            return _by_reference(plain, V, L)
        if element is not None:  # a[i], p[i]: an element of a number or location array, likewise
            return _by_reference(array_key(element.group(1), [i(V) for i in indexes]), V, L)
        if number is not None:
            result = float(number(V))
            return Argument("N", lambda: result)
        if location is not None:
            where = location(V).location()
            return Argument("L", lambda: where)
        raise ProgramError(f"CALL ARGUMENT {text} IS NOT A NUMBER OR A LOCATION")
    return argument


def _by_reference(name: str, V: dict[str, float], L: dict[str, Location]) -> Argument:
    if name in V or name not in L:
        def number_back(result: object) -> None:
            assert isinstance(result, float)
            V[name] = result
        current = V.get(name)
        return Argument("N", lambda: current, number_back)

    def location_back(result: object) -> None:
        assert isinstance(result, Location)
        L[name] = result
    here = L[name]
    return Argument("L", lambda: here, location_back)


def _try_number(text: str, machine: Machine) -> Fn | None:
    try:
        return compile_number(text, machine).function()
    except (ExprError, MachineError):
        return None


def _try_location(text: str, machine: Machine) -> Callable[[Values], Transform] | None:
    try:
        return compile_location(text, machine)
    except (ExprError, MachineError):
        return None


def _call(c: Build, st: Statement) -> Op:
    name, texts = st.args
    arguments = tuple(_argument(c, t) for t in texts if t)
    if st.command == "CALLS":  # the program a string names when the step runs
        named = compile_string(name, controller_of(c))
        return VCallS(c.step, c.next, c.next, "", arguments=arguments, machine=controller_of(c),
                      variables=c.variables, locations=c.sim.locations, named=named)
    return VCall(c.step, c.next, c.next, name, arguments=arguments, machine=controller_of(c), variables=c.variables,
                 locations=c.sim.locations)


CALLS: dict[str, Builder] = {"CALL": _call, "CALLS": _call}
