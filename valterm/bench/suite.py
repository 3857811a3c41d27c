"""``valterm bench``: speed figures measured against the project's goals.

Benchmarks report; tests do not time. Each entry is measured on this machine, one core,
best of a few repeats so a busy moment does not decide the figure.
"""

from __future__ import annotations

import math
import time
from typing import Any, Callable

import numpy as np

from valterm.core.kinematics import fk, fk_batch, fk_fast, ik, ik_batch, ik_fast, indicators, robot_geometry

GOALS = {
    "fk_single_us": ("<=", 5.0),
    "ik_single_us": ("<=", 10.0),
    "ik_batch_poses_per_s": (">=", 1_000_000.0),
    "interpreter_statements_per_s": (">=", 500_000.0),
    "collision_step_thesis_us": ("<=", 100.0),
    "collision_step_fcl_us": ("<=", 60.0),
    "raster_ms_200x60": ("<=", 2.0),
    "app_start_to_main_menu_s": ("<=", 1.0),
    "app_move_fps_160x50": (">=", 30.0),
    "app_move_bytes_per_frame_160x50": ("<=", 10_240.0),
}


def best_of(func: Callable[[], Any], number: int, repeat: int = 5) -> float:
    """Seconds per call, the best of ``repeat`` runs of ``number`` calls."""
    best = math.inf
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            func()
        best = min(best, (time.perf_counter() - start) / number)
    return best


def kinematics_entries() -> dict[str, float]:
    joints = [-20.0, -150.0, 40.0, 10.0, 50.0, 20.0]
    radians = [math.radians(j) for j in joints]
    pose = fk(joints)
    config = indicators(joints)
    xyz = [float(v) for v in pose.xyz]
    rotation = pose.rotation.tolist()
    rng = np.random.default_rng(0)
    many = rng.uniform(robot_geometry().stops_array[:, 0], robot_geometry().stops_array[:, 1], (100_000, 6))
    xyz_many, rot_many = fk_batch(many)
    cfg_many = np.tile(np.array(config), (len(many), 1))
    fk_batch_s = best_of(lambda: fk_batch(many), 1, 3)
    ik_batch_s = best_of(lambda: ik_batch(xyz_many, rot_many, cfg_many), 1, 3)
    return {
        "fk_single_us": best_of(lambda: fk_fast(*radians), 20_000) * 1e6,
        "fk_single_with_arrays_us": best_of(lambda: fk(joints), 20_000) * 1e6,
        "ik_single_us": best_of(lambda: ik_fast(*xyz, rotation, config.arm, config.elbow, config.wrist), 20_000) * 1e6,
        "ik_single_with_stops_us": best_of(lambda: ik(xyz, rotation, config, joints), 20_000) * 1e6,
        "fk_batch_poses_per_s": len(many) / fk_batch_s,
        "ik_batch_poses_per_s": len(many) / ik_batch_s,
    }


def _optional(entries: dict[str, Any], name: str, func: Callable[[], dict[str, float]]) -> None:
    """Areas built separately add their entries; a missing one is said, not hidden."""
    try:
        entries.update(func())
    except ImportError as error:
        entries.setdefault("missing", []).append(f"{name}: {error}")


def run_all() -> dict[str, Any]:
    entries: dict[str, Any] = {}
    entries.update(kinematics_entries())
    _optional(entries, "interpreter", _interpreter_entries)
    _optional(entries, "collision", _collision_entries)
    _optional(entries, "raster", _raster_entries)
    _optional(entries, "app", _app_entries)
    entries["goals"] = {
        key: {"goal": f"{op} {value:g}", "met": _met(entries.get(key), op, value)}
        for key, (op, value) in GOALS.items() if key in entries
    }
    return entries


def _met(value: float | None, op: str, goal: float) -> bool | None:
    if value is None:
        return None
    return value <= goal if op == "<=" else value >= goal


def _interpreter_entries() -> dict[str, float]:
    from valterm.bench.interpreter import bench_interpreter

    return {"interpreter_statements_per_s": float(bench_interpreter())}


def _collision_entries() -> dict[str, float]:
    """One motion step's check in the PROCESS cell, the clamp open around part 1 at A."""
    from valterm.bench.collision import bench_collision_step
    from valterm.core.files.locations import read_locations
    from valterm.core.files.setup import read_setup
    from valterm.core import resources
    from valterm.core.simulator import Simulator

    sim = Simulator(read_setup(resources.data_path("cells", "PROCESS.SET")))
    sim.locations.update(read_locations(resources.data_path("programs", "PROCESS.LOC")))
    sim.set_indicator("LEFTY")
    for _ in sim.move("A"):
        pass
    links = list(zip(sim.model.names, sim.robot_polyhedra()))
    result = bench_collision_step(links, sim.cell.objects)
    return {
        "collision_step_thesis_us": float(result["thesis_us_per_step"]),
        "collision_step_fcl_us": float(result["fcl_us_per_step"]),
    }


def _raster_entries() -> dict[str, float]:
    from valterm.bench.raster import bench_raster

    return {
        "raster_ms_80x24": float(bench_raster(80, 24)),
        "raster_ms_200x60": float(bench_raster(200, 60)),
    }


def _app_entries() -> dict[str, float]:
    """The real app under a pseudo-terminal at 160x50: start time, frames and bytes of a MOVE."""
    from valterm.bench.pty import bench_app

    return bench_app(160, 50)
