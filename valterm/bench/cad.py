"""Timing of a large mesh import (wired into `valterm bench`): the issue-24 figure, a
2-million-triangle binary STL, once, in a process of its own (its peak memory is the
process's, read from ``wait4``). No textual import."""

from __future__ import annotations

import os
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


def bench_stl_import(n: int = 1000) -> dict[str, float]:
    """Seconds and peak megabytes of ``valterm import`` of a 2 n²-triangle STL."""
    with tempfile.TemporaryDirectory() as folder:
        stl = Path(folder) / "torus.stl"
        triangles = torus_stl(stl, n)
        argv = [sys.executable, "-m", "valterm", "--workspace", str(Path(folder) / "ws"), "import", str(stl),
                "--out", "TORUS"]
        start = time.perf_counter()
        process = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(process.pid, 0)
        seconds = time.perf_counter() - start
        process.returncode = os.waitstatus_to_exitcode(status)
        if process.returncode != 0:
            raise RuntimeError(f"valterm import of {triangles} triangles failed ({process.returncode})")
    return {"cad_import_2m_triangles_s": seconds, "cad_import_2m_triangles_mb": usage.ru_maxrss / 1024,
            "cad_import_triangles": float(triangles)}
