"""The events are frozen dataclasses made when first used, not at import (issue 25, the start):
whatever touches them first, they are the same dataclasses."""

from __future__ import annotations

import dataclasses
import pickle
import subprocess
import sys

import pytest

from valterm.core import events
from valterm.core.events import Event, Grasp, Motion, Where


def _fresh(code: str) -> str:
    out = subprocess.run([sys.executable, "-c", f"from valterm.core import events as E\n{code}"],
                         capture_output=True, text=True, check=True)
    return out.stdout.strip()


@pytest.mark.parametrize(("first", "shown"), [
    ("print(E._PENDING != [])", "True"),  # nothing made at import
    ("print([f.name for f in dataclasses.fields(E.Grasp)])", "['program', 'step', 'clamp', 'part']"),
    ("print(E.Motion.__match_args__)", "('kind', 'steps', 'joints', 'seconds')"),
    ("print(dataclasses.is_dataclass(E.Where), E._PENDING)", "True []"),
    ("print(E.Grasp(3, step=2, program='P'))", "Grasp(program='P', step=2, clamp=(), part=3)"),
])
def test_whatever_touches_them_first_they_are_dataclasses(first: str, shown: str) -> None:
    assert _fresh(f"import dataclasses\n{first}") == shown


def test_an_event_unpickled_before_any_was_made_is_whole() -> None:
    data = pickle.dumps(Motion("joint", 3, (1.0, 2.0)))
    shown = _fresh(f"import pickle\nm = pickle.loads({data!r})\nprint(repr(m), m == E.Motion('joint', 3, (1.0, 2.0)))")
    assert shown == "Motion(kind='joint', steps=3, joints=(1.0, 2.0), seconds=0.0) True"


def test_once_made_each_is_a_frozen_dataclass_with_its_own_methods() -> None:
    Motion("joint", 1, ())
    assert events._PENDING == []
    kinds = [k for k in vars(events).values() if isinstance(k, type) and issubclass(k, Event)]
    assert len(kinds) >= 25
    for kind in kinds:
        assert kind.__dataclass_params__.frozen  # type: ignore[attr-defined]
        assert {"__init__", "__repr__", "__eq__", "__hash__", "__setattr__"} <= set(vars(kind)), kind
        assert "__setstate__" not in vars(kind)
    where = Where((1.0, 2.0, 3.0), (0.0, 90.0, 0.0), (0.0,) * 6)
    with pytest.raises(dataclasses.FrozenInstanceError):
        where.clamp = "CLOSED"  # type: ignore[misc]
    assert hash(Grasp(4)) == hash(Grasp(4)) and Grasp(4) != Grasp(5)
    assert pickle.loads(pickle.dumps(where)) == where and where.to_json()["clamp"] == "OPENED"
