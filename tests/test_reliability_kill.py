"""kill -9 during saves and during first use: every file whole (old or new), no stray
temporaries after the next open (issue 16).

A forked child saves (or seeds workspaces) in a loop and is killed with SIGKILL at a random
moment. ``VALTERM_KILL_TRIALS`` sets the number of trials of each kind (default 20; the
issue's 500 by hand: ``VALTERM_KILL_TRIALS=250``).
"""

from __future__ import annotations

import os
import random
import signal
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from valterm.core.files.locations import format_locations
from valterm.core.files.programs import Program, ProgramLine, format_program
from valterm.core.files.variables import format_variables
from valterm.core.files.atomic import is_temporary
from valterm.core.kinematics import Location
from valterm.core.workspace import Workspace, bundled_workspace_files

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork and SIGKILL")

TRIALS = int(os.environ.get("VALTERM_KILL_TRIALS", "20"))
SEED = int(os.environ.get("VALTERM_KILL_SEED", str(random.randrange(1 << 30))))


def _killed_at_random(work: Callable[[], None], rng: random.Random, longest: float) -> None:
    """Fork; the child does ``work`` forever; kill -9 it a random time after it started."""
    ready_r, ready_w = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: never returns into pytest
        try:
            os.close(ready_r)
            os.write(ready_w, b"r")
            while True:
                work()
        finally:
            os._exit(0)
    os.close(ready_w)
    os.read(ready_r, 1)
    os.close(ready_r)
    time.sleep(rng.uniform(0.0, longest))
    os.kill(pid, signal.SIGKILL)
    os.waitpid(pid, 0)


def _points(count: int, offset: float) -> dict[str, Location]:
    return {f"P{i}": Location((offset + i, 2.0 * i, -3.0), (0.0, 90.0, float(i % 360))) for i in range(count)}


def _temporaries(folder: Path) -> list[str]:
    return [p.name for p in folder.iterdir() if is_temporary(p.name)]


def test_kill_during_saves_leaves_every_file_whole(tmp_path: Path) -> None:
    rng = random.Random(SEED)
    workspace = Workspace.open(tmp_path / "ws")
    versions = [_points(800, 0.0), _points(900, 5000.0)]  # ~50 KB each: the kill lands mid-write
    programs = [Program("SAVED", [ProgramLine(None, f"TYPE {i}") for i in range(n)]) for n in (300, 400)]
    old_loc = (workspace.root / "PROCESS.LOC").read_text()
    whole_loc = {old_loc, *(format_locations(v) for v in versions)}
    whole_dat = {format_program(p) for p in programs}
    whole_check = {"", *(format_variables({"ROW": float(n)}) for n in range(2))}
    stray = 0
    for trial in range(TRIALS):
        turn = [0]

        def save(turn: list[int] = turn) -> None:
            i = turn[0] = turn[0] + 1
            workspace.write_locations("PROCESS", versions[i % 2])
            workspace.write_program(programs[i % 2])
            workspace.write_variables({"ROW": float(i % 2)})

        _killed_at_random(save, rng, 0.05)
        root = workspace.root
        assert (root / "PROCESS.LOC").read_text() in whole_loc, f"trial {trial}, seed {SEED}"
        if (root / "SAVED.DAT").exists():
            assert (root / "SAVED.DAT").read_text() in whole_dat, f"trial {trial}, seed {SEED}"
        assert (root / "CHECK.DAT").read_text() in whole_check, f"trial {trial}, seed {SEED}"
        assert workspace.programs_directory()[-1:] in (["PROCESS"], ["SAVED"])
        stray += len(_temporaries(root))
        Workspace.open(root)
        assert _temporaries(root) == [], f"trial {trial}, seed {SEED}"
    print(f"{TRIALS} kills during saves, {stray} temporaries left and removed (seed {SEED})")


def test_kill_during_first_use_leaves_a_workspace_that_repairs_itself(tmp_path: Path) -> None:
    rng = random.Random(SEED + 1)
    bundled = {name: source.read_bytes() for name, source in bundled_workspace_files()}
    for trial in range(TRIALS):
        base = tmp_path / f"t{trial}"
        base.mkdir()
        counter = [0]

        def seed_one(base: Path = base, counter: list[int] = counter) -> None:
            counter[0] += 1
            Workspace.open(base / str(counter[0]))

        _killed_at_random(seed_one, rng, 0.08)
        for root in base.iterdir():
            for name, data in bundled.items():  # before the next open: whole or absent
                if (root / name).exists():
                    assert (root / name).read_bytes() == data, f"{root.name}/{name}, trial {trial}, seed {SEED}"
            workspace = Workspace.open(root)
            for name, data in bundled.items():
                assert (root / name).read_bytes() == data, f"{root.name}/{name}, trial {trial}, seed {SEED}"
            assert workspace.programs_directory() == ["CONV1", "CONV2", "PROCESS"]
            assert _temporaries(root) == []
