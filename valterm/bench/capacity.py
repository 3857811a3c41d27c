"""How many sessions a host carries (docs/SERVING.md): one app in a pseudo-terminal, what it
costs while a student is idle, types, and runs a program, at a small and a large terminal.

    python -m valterm.bench.capacity [--seconds 20]

For each state: the app's CPU in cores (CPU seconds from /proc over the state's wall-clock
seconds: other processes' time is not counted, so it holds on a loaded host), the bytes it
wrote to the terminal a second, and its memory: the proportional set size (PSS, shared pages
split between the processes sharing them; /proc/PID/smaps_rollup) and the private dirty pages
(what one more session adds). Not part of ``valterm bench``'s goals: it informs the serving
guide's capacity table.
"""

from __future__ import annotations

import argparse
import math
import os
import tempfile
import time

from valterm.bench.pty import (
    LOOPS_DAT,
    _define_locations,
    _drain,
    _end,
    _line,
    _read_until,
    _record,
    _spawn,
    cpu_seconds,
)

TYPED = "WHERE\r"  # typed again and again at a person's pace: the line echoes, WHERE answers
PACE = 0.3  # seconds between keys


def memory_kib(pid: int) -> dict[str, float]:
    """The process's PSS and private dirty pages, KiB (smaps_rollup)."""
    found = {"Pss": math.nan, "Private_Dirty": math.nan}
    with open(f"/proc/{pid}/smaps_rollup", encoding="ascii") as rollup:
        for line in rollup:
            name, _, rest = line.partition(":")
            if name in found:
                found[name] = float(rest.split()[0])
    return {"pss_kib": found["Pss"], "private_kib": found["Private_Dirty"]}


def _state(pid: int, fd: int, seconds: float, keys: str = "") -> dict[str, float]:
    """CPU cores and bytes a second over ``seconds``, the keys typed at ``PACE`` meanwhile."""
    cpu, start, written = cpu_seconds(pid), time.perf_counter(), 0
    if keys:
        typed = 0
        while time.perf_counter() - start < seconds or typed % len(keys):  # whole commands
            os.write(fd, keys[typed % len(keys)].encode())
            typed += 1
            written += sum(n for _, n, _ in _record(fd, PACE, quiet_end=math.inf))
    else:
        written = sum(n for _, n, _ in _record(fd, seconds, quiet_end=math.inf))
    wall = time.perf_counter() - start
    return {"cores": (cpu_seconds(pid) - cpu) / wall, "bytes_per_s": written / wall, **memory_kib(pid)}


def measure(width: int, height: int, seconds: float) -> dict[str, dict[str, float]]:
    """Idle at the MAIN MENU, typing in VAL-II mode, and a looping program at real pace."""
    workspace = tempfile.mkdtemp(prefix="valterm-capacity-")
    with open(os.path.join(workspace, "LOOPS.DAT"), "w", encoding="ascii") as program:
        program.write(LOOPS_DAT)
    pid, fd = _spawn(width, height, workspace)
    try:
        _read_until(fd, b"MAIN MENU", 30.0)
        _drain(fd, 1.0)
        states = {"idle": _state(pid, fd, seconds)}
        _define_locations(fd)  # VAL-II mode's command line, PROCESS.LOC's locations defined
        states["typing"] = _state(pid, fd, seconds, keys=TYPED)
        _line(fd, "EXECUTE LOOPS,-1")
        _record(fd, 1.0, quiet_end=math.inf)  # under way (a drain would wait for a quiet the run never has)
        states["running"] = _state(pid, fd, seconds)
    finally:
        _end(pid, fd)
    return states


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="seconds a state (default 20)")
    parser.add_argument("--served", action="store_true",
                        help="as docs/valterm-login.sh serves it: 256 colours, 20 frames a second")
    args = parser.parse_args(argv)
    if args.served:  # the login wrapper's defaults (docs/valterm-login.sh)
        os.environ.update(TEXTUAL_COLOR_SYSTEM="256", TEXTUAL_FPS="20")
    print(f"load {os.getloadavg()[0]:.1f}, {os.cpu_count()} cores, served: {args.served}")
    print("| terminal | state | cores | bytes/s | PSS MiB | private MiB |")
    print("|---|---|---:|---:|---:|---:|")
    for width, height in ((80, 24), (160, 50)):
        for state, figures in measure(width, height, args.seconds).items():
            print(f"| {width}x{height} | {state} | {figures['cores']:.3f} | {figures['bytes_per_s']:,.0f} | "
                  f"{figures['pss_kib'] / 1024:.1f} | {figures['private_kib'] / 1024:.1f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
