"""Timing of a large mesh import (wired into `valterm bench`): the issue-24 figure, a
2-million-triangle binary STL, once, in a process of its own (its peak memory is the
process's own, which it says itself). No textual import."""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from valterm.core.cad.mesh import _STL_RECORD


def torus_stl(path: Path, n: int = 1000) -> int:
    """A binary STL of a torus (R 80 mm, r 25 mm) of n x n quads, 2 n² triangles; returns the count."""
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, n, endpoint=False), np.linspace(0, 2 * np.pi, n, endpoint=False),
                       indexing="ij")
    grid = np.stack([(80 + 25 * np.cos(v)) * np.cos(u), (80 + 25 * np.cos(v)) * np.sin(u), 25 * np.sin(v)], -1)
    i = np.arange(n)
    j = (i + 1) % n
    a, b, c, d = grid[i][:, i], grid[j][:, i], grid[j][:, j], grid[i][:, j]
    triangles = np.concatenate([np.stack([a, b, c], 2).reshape(-1, 3, 3), np.stack([a, c, d], 2).reshape(-1, 3, 3)])
    record = np.zeros(len(triangles), _STL_RECORD)
    record["vertices"] = triangles
    path.write_bytes(b"valterm bench torus".ljust(80) + np.uint32(len(record)).tobytes() + record.tobytes())
    return len(record)


# the import run in a process of its own that says its own peak (VmHWM: this process's
# pages at most, from its exec on); a child's ru_maxrss from wait4 also counts the pages of
# the bench process it was forked from (Linux keeps the old image's high-water mark across
# exec), so a bench grown to 900 MB read as a 900 MB import; -P: the folder it runs in is
# not looked in for modules
MEASURED = """
import sys
from valterm.cli import main
try:
    status = main(sys.argv[2:])
finally:
    with open("/proc/self/status") as lines:
        peak = next(line.split()[1] for line in lines if line.startswith("VmHWM:"))
    with open(sys.argv[1], "w") as out:
        out.write(peak)
raise SystemExit(status)
"""


def peak_of(args: list[str], folder: Path) -> tuple[float, float]:
    """Seconds and peak megabytes of ``valterm ARGS`` in a process of its own (see MEASURED)."""
    said = folder / "peak-kb"
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-P", "-c", MEASURED, str(said), *args], stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL, check=False)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"valterm {' '.join(args[2:3])} failed ({done.returncode})")
    return seconds, int(said.read_text()) / 1024


def bench_stl_import(n: int = 1000) -> dict[str, float]:
    """Seconds and peak megabytes of ``valterm import`` of a 2 n²-triangle STL."""
    with tempfile.TemporaryDirectory() as folder:
        stl = Path(folder) / "torus.stl"
        triangles = torus_stl(stl, n)
        seconds, mb = peak_of(["--workspace", str(Path(folder) / "ws"), "import", str(stl), "--out", "TORUS"],
                              Path(folder))
    return {"cad_import_2m_triangles_s": seconds, "cad_import_2m_triangles_mb": mb,
            "cad_import_triangles": float(triangles)}
