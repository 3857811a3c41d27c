"""V+ assignments and control: FOR, CASE, IF, WHILE, UNTIL, EXIT, NEXT.
"""

from __future__ import annotations

from valterm.core.val import builders as shared
from valterm.core.val.builders import Build, Builder
from valterm.core.val.dialects.vplus.compiled import (
    condition_of,
    controller_of,
    location_of,
    number_of,
    store_location,
)
from valterm.core.val.dialects.vplus.expr import (
    array_key,
    compile_number,
    compile_precision,
    compile_string,
)
from valterm.core.val.dialects.vplus.statements import TUNING
from valterm.core.val.expr import Fn, Values
from valterm.core.val.ops import (
    Assign,
    Branch,
    Events,
    Op,
    ProgramError,
)
from valterm.core.val.parser import (
    ASSIGN,
    Statement,
)


def _assign(c: Build, st: Statement) -> Op:
    kind, target, index_texts, value_text = st.args
    machine = controller_of(c)
    if kind == "N" and not index_texts:
        return Assign(c.step, c.next, c.next, target, number_of(c, value_text))
    indexes = [number_of(c, i) for i in index_texts]

    def key(V: Values) -> str:
        return array_key(target, [i(V) for i in indexes]) if indexes else target

    if kind == "S":
        value_s = compile_string(value_text, machine)

        def run_s() -> Events:
            machine.strings[key(c.variables)] = value_s(c.variables)
            return c.next
            yield
        return c.action(run_s)
    if kind == "P":  # SET #p = #PPOINT(...) or #q
        value_p = compile_precision(value_text, machine)

        def run_p() -> Events:
            machine.precision[key(c.variables)] = value_p(c.variables)
            return c.next
            yield
        return c.action(run_p)
    if kind == "L":
        value_l = location_of(c, value_text)

        def run_l() -> Events:
            store_location(c, key(c.variables), value_l(c.variables))
            return c.next
            yield
        return c.action(run_l)
    value_n = number_of(c, value_text)

    def run_n() -> Events:
        c.variables[key(c.variables)] = float(value_n(c.variables))
        return c.next
        yield
    return c.action(run_n)


def _for(c: Build, st: Statement) -> Op:
    var, start_text, stop_text, step_text = st.args
    start, stop = number_of(c, start_text), number_of(c, stop_text)
    step = number_of(c, step_text) if step_text else (lambda V: 1.0)
    end = c.after(c.partner())
    V = c.variables

    def run() -> Events:
        V[var] = float(start(V))
        return c.next if _within(V[var], stop(V), step(V)) else end
        yield
    return c.action(run)


def _within(value: float, stop: float, step: float) -> bool:
    if step == 0:
        raise ProgramError("FOR: STEP IS 0")
    return value <= stop + 1e-9 if step > 0 else value >= stop - 1e-9


def _end(c: Build, st: Statement) -> Op:
    assert c.analysis is not None
    opener = c.analysis.partner.get(c.index)
    statement = c.analysis.statements[opener] if opener is not None else None
    if statement is None or statement.command != "FOR" or opener is None:
        return shared.end_block(c, st)
    var, _start, stop_text, step_text = statement.args
    stop = number_of(c, stop_text)
    step = number_of(c, step_text) if step_text else (lambda V: 1.0)
    body = c.op_index[opener + 1]
    V = c.variables

    def run() -> Events:
        increment = float(step(V))
        V[var] = V[var] + increment
        return body if _within(V[var], stop(V), increment) else c.next
        yield
    return c.action(run)


def _case(c: Build, st: Statement) -> Op:
    assert c.analysis is not None
    value = number_of(c, st.args[0])
    end = c.after(c.partner())
    choices: list[tuple[list[Fn] | None, int]] = []
    for index in c.analysis.cases.get(c.index, []):
        statement = c.analysis.statements[index]
        assert statement is not None
        values = None if statement.command == "ANY" else [number_of(c, t) for t in statement.args]
        choices.append((values, c.after(index)))

    def run() -> Events:
        V = c.variables
        wanted = value(V)
        for values, target in choices:
            if values is None or any(v(V) == wanted for v in values):
                return target
        return end
        yield
    return c.action(run)


def _value_or_any(c: Build, st: Statement) -> Op:
    """Reached by falling out of the previous choice: the CASE is done."""
    assert c.analysis is not None
    case = c.analysis.case_of[c.index]
    return c.jump(c.after(c.analysis.partner[case]))


def _branch(c: Build, text: str, if_true: int, if_false: int, error: int | None = None) -> Branch:
    return Branch(c.step, c.next, c.next if error is None else error, condition_of(c, text), if_true, if_false)


def _if(c: Build, st: Statement) -> Op:
    if st.shape == 1:
        target = c.target_of(st.args[1])
        if target is None:
            return shared.if_goto(c, Statement("IF", (compile_number(st.args[0], c.machine), st.args[1])))
        return _branch(c, st.args[0], target, c.next)
    assert c.analysis is not None
    end = c.after(c.partner())
    otherwise = c.analysis.else_of.get(c.index)
    return _branch(c, st.args[0], c.next, c.after(otherwise) if otherwise is not None else end, end)


def _while(c: Build, st: Statement) -> Op:
    end = c.after(c.partner())
    return _branch(c, st.args[0], c.next, end, end)


def _until(c: Build, st: Statement) -> Op:
    return _branch(c, st.args[0], c.next, c.after(c.partner()))


def _exit_or_next(c: Build, st: Statement) -> Op:
    """EXIT n: past the end of the n-th enclosing loop; NEXT n: that loop's next pass (FOR:
    its END steps the variable; WHILE: the condition again; DO: its UNTIL)."""
    assert c.analysis is not None
    loops, count = c.analysis.loops.get(c.index, []), st.args[0]
    if count > len(loops):
        return shared.failed(c, f"{st.command} {count}: NOT INSIDE {count} LOOP(S)")
    opener = loops[count - 1]
    closer = c.analysis.partner.get(opener)
    if closer is None:
        return shared.failed(c, f"{st.command}: ITS LOOP IS NOT CLOSED")
    if st.command == "EXIT":
        return c.jump(c.after(closer))
    kind = c.analysis.statements[opener]
    return c.jump(c.op_index[opener if kind is not None and kind.command == "WHILE" else closer])


def _nothing(c: Build, st: Statement) -> Op:
    return c.jump(c.next)


CONTROL: dict[str, Builder] = {
    ASSIGN: _assign, "FOR": _for, "END": _end, "CASE": _case, "VALUE": _value_or_any, "ANY": _value_or_any,
    "IF": _if, "WHILE": _while, "UNTIL": _until, "EXIT": _exit_or_next, "NEXT": _exit_or_next,
    "AUTO": _nothing, "GLOBAL": _nothing, "BREAK": _nothing, **{word: _nothing for word in TUNING},
    "ATTACH": _nothing, "DETACH": _nothing,
}
"""Assignments, the block structures, and the statements accepted with no effect."""
