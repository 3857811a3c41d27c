"""``valterm bench``: speed figures measured against the project's goals.

Benchmarks report; tests do not time. Each entry is measured on this machine, one core,
the median of several rounds; the peers (the old collision path, python-fcl, drawille,
Robotics Toolbox when installed) are timed in the same run so their ratios hold on a busy
machine even when the absolute figures do not.
"""

from __future__ import annotations

import math
import time
from typing import Any, Callable

import numpy as np

from valterm.core.kinematics import fk, fk_batch, fk_fast, ik, ik_batch, ik_fast, indicators, robot_geometry

GOALS: dict[str, tuple[str, float]] = {
    "collision_per_pose_us_30parts": ("<=", 60.0),
    "collision_step_thesis_us": ("<=", 100.0),
    "collision_step_fcl_us": ("<=", 60.0),
    "collision_scaling_exponent": ("<", 1.0),
    "collision_run_vs_fcl_x_30parts": ("<=", 2.0),
    "collision_check_vs_fcl_x_100parts": ("<=", 3.0),
    "collision_check_vs_fcl_x_300parts": ("<=", 3.0),
    # issue 40: the scenes users meet (valterm.bench.collision_scenes), beside fcl in the same run
    "collision_crowded_vs_fcl_x_30parts": ("<=", 4.0),
    "collision_crowded_vs_fcl_x_100parts": ("<=", 4.0),
    "collision_crowded_vs_ccd_x_30parts": ("<=", 0.5),
    "collision_crowded_vs_ccd_x_100parts": ("<=", 0.5),
    "collision_heavy_vs_ccd_x_30parts": ("<=", 0.5),
    "collision_heavy_vs_ccd_x_100parts": ("<=", 0.5),
    "raster_vs_drawille_x": (">=", 50.0),
    "ik_single_us": ("<=", 8.0),
    "ik_random_vs_rtb_x": (">=", 50.0),
    "ik_batch_poses_per_s": (">=", 2_000_000.0),
    "ik_batch_bytes_per_pose": ("<=", 200.0),
    "fk_batch_poses_per_s": (">=", 3_000_000.0),
    "fk_single_us": ("<=", 5.0),
    "interpreter_statements_per_s": (">=", 500_000.0),
    "grade_s_per_student": ("<=", 2.0),  # issue 24: the whole `valterm grade` command
    "grade_jobs2_speedup_x": (">=", 1.7),  # issue 40: warm workers, wall clock, two idle cores
    "run_json_statements_per_s": (">=", 500_000.0),
    # issue 40: run's output in blocks whatever PYTHONUNBUFFERED says; the transcript as fast
    "run_json_unbuffered_statements_per_s": (">=", 2_000_000.0),
    "run_text_statements_per_s": (">=", 2_000_000.0),
    "run_text_unbuffered_statements_per_s": (">=", 2_000_000.0),
    "app_start_to_main_menu_s": ("<=", 1.0),
    "app_start_vs_bare_x": ("<=", 1.5),
    "app_start_picture_vs_bare_x": ("<=", 1.3),  # issue 40: the picture beside the menu
    "app_move_fps_160x50": (">=", 30.0),
    "app_move_bytes_per_frame_160x50": ("<=", 10_240.0),
    "app_program_fps_160x50": (">=", 30.0),
    # issue 40: a running session at a tenth of a core (PROCESS at real pace, 160x50)
    "app_program_bytes_per_frame_160x50": ("<=", 3_072.0),
    "app_program_cores_160x50": ("<=", 0.10),
    "cad_import_2m_triangles_s": ("<", 10.0),
    "cad_import_2m_triangles_mb": ("<", 1024.0),
}

# the peer measured in the same run, shown beside a goal's figure in ``--md``
PEERS = {
    "collision_per_pose_us_30parts": ("collision_per_pose_old_us_30parts", "the pre-issue-15 path, µs"),
    "collision_step_thesis_us": ("collision_step_fcl_us", "python-fcl, µs"),
    "collision_step_fcl_us": ("collision_step_fcl_polyhedra_us", "fcl on placed polyhedra (before), µs"),
    "raster_vs_drawille_x": ("drawille_process_ms_200x60", "drawille, ms per frame"),
    "ik_single_us": ("rtb_ikine_a_us", "Robotics Toolbox ikine_a, µs"),
    "app_start_vs_bare_x": ("app_start_bare_textual_s", "a bare Textual app, s"),
    "grade_jobs2_speedup_x": ("grade_jobs1_s", "--jobs 1, s (60 students)"),
    "app_start_picture_vs_bare_x": ("app_start_bare_textual_s", "a bare Textual app, s"),
    "collision_scaling_exponent": ("collision_thesis_us_300parts", "µs per pose at 300 parts"),
    "collision_run_vs_fcl_x_30parts": ("collision_run_fcl_us_30parts", "python-fcl, µs per pose"),
    "collision_check_vs_fcl_x_100parts": ("collision_check_fcl_us_100parts", "python-fcl, µs per pose"),
    "collision_check_vs_fcl_x_300parts": ("collision_check_fcl_us_300parts", "python-fcl, µs per pose"),
    **{f"collision_{cell}_vs_{peer}_x_{n}parts": (f"collision_{cell}_{peer}_us_{n}parts", f"{name}, µs per pose")
       for cell in ("crowded", "heavy") for n in (30, 100)
       for peer, name in (("fcl", "python-fcl per pose"), ("ccd", "fcl per pose + continuousCollide"))},
    "app_program_fps_160x50": ("app_program_bare_fps_160x50", "a bare Textual app animating a widget the picture's size, frames/s"),
    "app_program_bytes_per_frame_160x50": ("app_program_bare_bytes_per_frame_160x50", "the bare Textual app, bytes a frame"),
    "app_program_cores_160x50": ("app_program_bare_cores_160x50", "the bare Textual app at the same frame rate, cores"),
    "run_json_statements_per_s": ("interpreter_statements_per_s", "the same loop without output, statements/s"),
    "run_json_unbuffered_statements_per_s": ("run_json_statements_per_s", "buffered standard output, statements/s"),
    "run_text_statements_per_s": ("run_json_statements_per_s", "--json, statements/s"),
    "run_text_unbuffered_statements_per_s": ("run_text_statements_per_s", "buffered standard output, statements/s"),
}

# a figure shown beside a goal's row in ``--md``, so the two are read together
BESIDE = {
    **{f"collision_crowded_vs_fcl_x_{n}parts": (f"collision_crowded_differ_fcl_{n}parts",
                                               "pairs found differently from fcl per pose (no goal)") for n in (30, 100)},
    **{f"collision_crowded_vs_ccd_x_{n}parts": (f"collision_crowded_us_{n}parts", "valterm, µs per pose (no goal)")
       for n in (30, 100)},
    **{f"collision_heavy_vs_ccd_x_{n}parts": (f"collision_heavy_differ_ccd_{n}parts",
                                             "pairs found differently from fcl + CCD, below (no goal)") for n in (30, 100)},
    "app_start_vs_bare_x": ("app_start_picture_vs_bare_x", "the model's picture beside the menu, x"),
    "app_start_picture_vs_bare_x": ("app_start_picture_cold_vs_bare_x",
                                    "a set-up's first start (no picture kept), x (no goal)"),
}

ROUNDS = 7


def median_of(func: Callable[[], Any], number: int, rounds: int = ROUNDS) -> float:
    """Seconds per call, the median of ``rounds`` runs of ``number`` calls (after one warm-up)."""
    func()
    runs = []
    for _ in range(rounds):
        start = time.perf_counter()
        for _ in range(number):
            func()
        runs.append((time.perf_counter() - start) / number)
    return float(np.median(runs))


def _bytes_per_pose(func: Callable[[], Any], n: int) -> float:
    """Peak memory a batch call allocates (numpy reports to tracemalloc), per pose."""
    import tracemalloc

    tracemalloc.start()
    try:
        func()
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return peak / n


def kinematics_entries() -> dict[str, float]:
    joints = [-20.0, -150.0, 40.0, 10.0, 50.0, 20.0]
    r1, r2, r3, r4, r5, r6 = (math.radians(j) for j in joints)
    pose = fk(joints)
    config = indicators(joints)
    x, y, z = (float(v) for v in pose.xyz)
    rotation = pose.rotation.tolist()
    rng = np.random.default_rng(0)
    stops = robot_geometry().stops_array
    entries: dict[str, float] = {
        "fk_single_us": median_of(lambda: fk_fast(r1, r2, r3, r4, r5, r6), 20_000) * 1e6,
        "fk_single_with_arrays_us": median_of(lambda: fk(joints), 20_000) * 1e6,
        "ik_fast_us": median_of(lambda: ik_fast(x, y, z, rotation, config.arm, config.elbow, config.wrist), 20_000) * 1e6,
        # the public call as the simulator makes it: numpy xyz and rotation, stops fitted
        "ik_single_us": median_of(lambda: ik(pose.xyz, pose.rotation, config, joints), 20_000) * 1e6,
    }
    # issue 25: one call on random in-range poses (most have JT4 or JT6 beyond +-94 degrees,
    # where a 360-degree equivalent is within the stops too), from the pose itself as current
    cases = []
    for q in rng.uniform(stops[:, 0], stops[:, 1], (400, 6)).tolist():
        p = fk(q)
        cases.append((p.xyz, p.rotation, indicators(q), q))

    def random_poses() -> None:
        for xyz_, rot_, cfg_, q_ in cases:
            ik(xyz_, rot_, cfg_, q_)

    entries["ik_random_us"] = median_of(random_poses, 20) / len(cases) * 1e6
    for n in (100_000, 1_000_000):
        many = rng.uniform(stops[:, 0], stops[:, 1], (n, 6))
        xyz_many, rot_many = fk_batch(many)
        cfg_many = np.tile(np.array(config), (n, 1))
        rounds = 5 if n <= 100_000 else 3
        entries[f"fk_batch_poses_per_s_{n}"] = n / median_of(lambda: fk_batch(many), 1, rounds)
        entries[f"ik_batch_poses_per_s_{n}"] = n / median_of(lambda: ik_batch(xyz_many, rot_many, cfg_many), 1, rounds)
        if n == 100_000:
            entries["fk_batch_bytes_per_pose"] = _bytes_per_pose(lambda: fk_batch(many), n)
            entries["ik_batch_bytes_per_pose"] = _bytes_per_pose(lambda: ik_batch(xyz_many, rot_many, cfg_many), n)
    entries["fk_batch_poses_per_s"] = min(v for k, v in entries.items() if k.startswith("fk_batch_poses_per_s_"))
    entries["ik_batch_poses_per_s"] = min(v for k, v in entries.items() if k.startswith("ik_batch_poses_per_s_"))
    return entries


def _rtb_entries() -> dict[str, float]:
    """Robotics Toolbox's analytic PUMA 560 IK on its own model, when it is installed."""
    import roboticstoolbox as rtb

    puma = rtb.models.DH.Puma560()
    target = puma.fkine(puma.qn)
    return {"rtb_ikine_a_us": median_of(lambda: puma.ikine_a(target), 200) * 1e6}


def _optional(entries: dict[str, Any], name: str, func: Callable[[], dict[str, Any]]) -> None:
    """Areas built separately add their entries; a missing one is said, not hidden."""
    try:
        entries.update(func())
    except ImportError as error:
        entries.setdefault("missing", []).append(f"{name}: {error}")


def run_all(app: bool = True) -> dict[str, Any]:
    entries: dict[str, Any] = {"machine": _machine()}
    entries.update(kinematics_entries())
    _optional(entries, "Robotics Toolbox (pip install roboticstoolbox-python)", _rtb_entries)
    if "rtb_ikine_a_us" in entries:
        entries["ik_vs_rtb_x"] = entries["rtb_ikine_a_us"] / entries["ik_single_us"]
        entries["ik_random_vs_rtb_x"] = entries["rtb_ikine_a_us"] / entries["ik_random_us"]
    _optional(entries, "interpreter", _interpreter_entries)
    _optional(entries, "grade", _grade_entries)
    _optional(entries, "collision", _collision_entries)
    _optional(entries, "collision on a dense cell", _dense_entries)
    _optional(entries, "collision on crowded and heavy cells", _scene_entries)
    _optional(entries, "raster", _raster_entries)
    _optional(entries, "CAD import", _cad_entries)
    _optional(entries, "drawille (the bench extra: pip install 'valterm[bench]')", _drawille_entries)
    if app:
        _optional(entries, "app", _app_entries)
    entries["goals"] = {
        key: {"goal": f"{op} {value:g}", "met": _met(entries.get(key), op, value)}
        for key, (op, value) in GOALS.items() if key in entries
    }
    return entries


def _machine() -> str:
    import os
    import platform

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (f"{platform.machine()} {os.cpu_count()} cores, {platform.python_implementation()} "
            f"{platform.python_version()}, numpy {np.__version__}, load {load:.1f}")


def _met(value: float | None, op: str, goal: float) -> bool | None:
    if value is None:
        return None
    if op == "<":
        return value < goal
    return value <= goal if op == "<=" else value >= goal


def _interpreter_entries() -> dict[str, float]:
    """The interpreter alone, then ``valterm run``'s output: JSON or the text transcript, to
    standard output buffered or as with ``PYTHONUNBUFFERED=1`` (issue 40)."""
    from valterm.bench.interpreter import bench_interpreter, bench_run_output

    entries = {"interpreter_statements_per_s": float(bench_interpreter())}
    for kind, as_json in (("json", True), ("text", False)):
        entries[f"run_{kind}_statements_per_s"] = bench_run_output(as_json=as_json)
        entries[f"run_{kind}_unbuffered_statements_per_s"] = bench_run_output(as_json=as_json, unbuffered=True)
    return entries


def _grade_entries() -> dict[str, float]:
    from valterm.bench.grading import bench_grade, bench_grade_jobs

    return {"grade_s_per_student": bench_grade(), **bench_grade_jobs()}


def _collision_entries() -> dict[str, float]:
    """The PUMA model among n parts (``valterm.bench.collision.ring_cell``), a JT1 sweep."""
    from valterm.bench.collision import bench_collision_per_pose, bench_puma_step

    entries: dict[str, float] = {}
    per_pose = {}
    for n in (5, 30, 100, 300):
        found = bench_collision_per_pose(n, rounds=5)
        per_pose[n] = found["us_per_pose"]
        entries[f"collision_thesis_us_{n}parts"] = found["us_per_pose"]
        entries[f"collision_old_us_{n}parts"] = found["old_us_per_pose"]
        if n == 30:
            entries["collision_per_pose_us_30parts"] = found["us_per_pose"]
            entries["collision_per_pose_old_us_30parts"] = found["old_us_per_pose"]
            entries["collision_per_pose_speedup_x"] = found["old_us_per_pose"] / found["us_per_pose"]
    # slope of log(time) over log(parts) from 5 to 300: below 1 is sub-linear
    entries["collision_scaling_exponent"] = math.log(per_pose[300] / per_pose[5]) / math.log(300 / 5)
    step = bench_puma_step(30, rounds=5)
    entries["collision_step_thesis_us"] = step["thesis_us"]
    entries["collision_step_fcl_us"] = step["fcl_us"]
    entries["collision_step_fcl_polyhedra_us"] = step["fcl_polyhedra_us"]
    entries["collision_step_links"] = step["links"]
    entries["collision_step_moving_bodies"] = step["links"] + step["carried"]
    return entries


def _cad_entries() -> dict[str, float]:
    from valterm.bench.cad import bench_stl_import

    return bench_stl_import()


def _dense_entries() -> dict[str, float]:
    """Issue 25: a 600-MOVE program on a dense 30-part cell as ``run --collisions`` pays it, and
    the pose check on dense 100- and 300-part cells, each against plain python-fcl."""
    from valterm.bench.collision import bench_dense_check, bench_dense_run

    run = bench_dense_run(30, 600)
    entries = {"collision_run_us_30parts": run["us_per_pose"], "collision_run_fcl_us_30parts": run["fcl_us_per_pose"],
               "collision_run_poses_30parts": run["poses"],
               "collision_run_vs_fcl_x_30parts": run["us_per_pose"] / run["fcl_us_per_pose"]}
    for n in (100, 300):
        found = bench_dense_check(n)
        entries[f"collision_check_us_{n}parts"] = found["check_us"]
        entries[f"collision_swept_us_{n}parts"] = found["swept_us"]
        entries[f"collision_check_fcl_us_{n}parts"] = found["fcl_us"]
        entries[f"collision_check_vs_fcl_x_{n}parts"] = found["check_us"] / found["fcl_us"]
        entries[f"collision_swept_vs_fcl_x_{n}parts"] = found["swept_us"] / found["fcl_us"]
    return entries


def _scene_entries() -> dict[str, Any]:
    """Issue 40: a cell crowded round a program's path the arm clears, and a collision-heavy
    one with a 0.5 mm plate, at 30 and 100 parts, against python-fcl per pose and per pose +
    continuousCollide; where they find a pair differently, what the sampled path says."""
    from valterm.bench.collision_scenes import scene_figures

    figures, notes = scene_figures()
    return {**figures, "notes": notes}


def _raster_entries() -> dict[str, float]:
    from valterm.bench.raster import bench_raster

    return {
        "raster_ms_80x24": float(bench_raster(80, 24)),
        "raster_ms_200x60": float(bench_raster(200, 60)),
    }


def _app_entries() -> dict[str, float]:
    """The real app under a pseudo-terminal at 160x50: start time, then frames and bytes
    while a joint move plays and while the PROCESS program runs in VAL-II mode at the fastest
    playback factor, and PROCESS at real pace: robot drawings per second of motion, their
    bytes and the app's CPU, beside a bare Textual app animating a widget of the picture's size
    (CPU seconds hold on a busy machine; frames a second and start times need an idle one)."""
    from valterm.bench.pty import bench_app

    return bench_app(160, 50)


def _drawille_entries() -> dict[str, float]:
    from valterm.bench.raster import bench_raster_vs_drawille

    return bench_raster_vs_drawille(200, 60, rounds=ROUNDS)


def markdown(entries: dict[str, Any]) -> str:
    """The goals table (for docs/PERFORMANCE.md): figure, value, goal, met, peer in the same run."""
    lines = [f"Measured on: {entries.get('machine', '?')}", "",
             "| figure | value | goal | met | peer (same run) |", "|---|---:|---|---|---|"]
    for key, (op, goal) in GOALS.items():
        value = entries.get(key)
        if value is None:
            lines.append(f"| `{key}` | not measured | {op} {goal:g} | - | |")
            continue
        peer = ""
        if key in PEERS and PEERS[key][0] in entries:
            peer = f"{PEERS[key][1]}: {_fmt(entries[PEERS[key][0]])}"
        if key in BESIDE and BESIDE[key][0] in entries:
            peer = "; ".join(filter(None, [peer, f"{BESIDE[key][1]}: {_fmt(entries[BESIDE[key][0]])}"]))
        met = _met(value, op, goal)
        lines.append(f"| `{key}` | {_fmt(value)} | {op} {goal:g} | {'yes' if met else '**no**'} | {peer} |")
    for line in entries.get("missing", []):
        lines.append(f"\nNot measured: {line}")
    if entries.get("notes"):
        lines += ["", "Where the checkers differ:", ""] + [f"- {line}" for line in entries["notes"]]
    return "\n".join(lines)


def _fmt(value: float) -> str:
    if abs(value) >= 10_000:
        return f"{value:,.0f}"
    return f"{value:.3g}" if abs(value) < 10 else f"{value:.1f}"
