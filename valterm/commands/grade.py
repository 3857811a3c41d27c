"""``valterm grade TASK.toml SUBMISSION... [--jobs N] [--json FILE] [--junit FILE] [--gradescope FILE]``,
``valterm grade --merge RESULTS.json... [--json FILE] [--junit FILE]``

Grades students' programs against a task file the instructor writes (docs/GRADING.md): the
cell, the location files, where parts must end up (with a tolerance), the cycle time
allowed, whether collisions are allowed. Each SUBMISSION is a student's program file or
folder (its program, and the programs it CALLs), or a class: a folder of students' folders
(``grade TASK subs`` and ``grade TASK subs/*`` grade the same students, core/grading.py's
find_students). A submission is read only inside itself, never through a link. Students run in parallel
on worker processes started and warmed once for the class (``--jobs``, default: the number of
CPUs), each on its own fresh cell and variables; nothing is written to any workspace.
``--merge`` combines the ``--json`` results of shares of a class graded apart.

The terminal shows one row a student (PASS, or FAIL with the first failure named and
located); ``--json FILE`` and ``--junit FILE`` write every failure and finding (``-`` for
standard output). The run limits (``--max-steps``, ``--max-seconds``, ``--max-lines``)
apply to each program.

Exit 0: every submission passed; 1: one failed, or the task file is wrong; 2: usage.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

from valterm.commands import FAILURE, OK, USAGE, fail
from valterm.commands.limits import add_limit_flags

if TYPE_CHECKING:
    from concurrent.futures import ProcessPoolExecutor


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = subparsers.add_parser("grade", help="grade students' programs against a task file (table, JSON, JUnit XML)")
    parser.add_argument("task", metavar="TASK.toml", help="the task file (docs/GRADING.md)")
    parser.add_argument("submissions", metavar="SUBMISSION", nargs="*",
                        help="a student's program file or folder, or a class: a folder of students' folders")
    parser.add_argument("--merge", action="store_true",
                        help="combine the --json results of shares of a class graded apart: "
                             "grade --merge RESULTS.json... [--json FILE] [--junit FILE]")
    parser.add_argument("--jobs", type=int, default=0, metavar="N",
                        help="programs graded at once, one process each (default: the number of CPUs)")
    parser.add_argument("--json", metavar="FILE", help="write the results as JSON (- for standard output)")
    parser.add_argument("--junit", metavar="FILE", help="write the results as JUnit XML (- for standard output)")
    parser.add_argument("--gradescope", metavar="FILE",
                        help="write one submission's results as Gradescope's results.json (- for standard output)")
    add_limit_flags(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from valterm.core.errors import ValtermError
    from valterm.core.grading import Submission, check_task, find_students, read_task, run_limits

    if args.jobs < 0:
        return fail("grade: --jobs must be 0 (one per CPU) or more", USAGE)
    if [args.json, args.junit, args.gradescope].count("-") > 1:
        return fail("grade: only one of --json, --junit and --gradescope can go to standard output", USAGE)
    if args.merge:
        return _merge(args)
    if not args.submissions:
        return fail("grade: name the submissions to grade (or --merge RESULTS.json...)", USAGE)
    try:
        task = read_task(args.task)
        check_task(task)
        found = find_students(args.submissions)
    except (ValtermError, OSError) as error:
        return fail(error, FAILURE)
    if args.gradescope:
        if len(args.submissions) != 1:
            return fail(f"grade: --gradescope writes one submission's results (Gradescope grades one a run); "
                        f"{len(args.submissions)} were named", USAGE)
        if len(found) != 1:  # the one submission, whatever it holds: a FAIL that says why, not no results
            found = [Submission(Path(args.submissions[0]).name, Path(args.submissions[0]))]
    if not found:
        return fail("grade: no program files or folders to grade", FAILURE)
    started = time.perf_counter()
    limits = run_limits(task, getattr(args, "max_steps", None), getattr(args, "max_seconds", None),
                        getattr(args, "max_lines", None))  # the flags given, else the task's
    verdicts = _grade_all(task, found, limits, args.jobs or os.cpu_count() or 1)
    elapsed = time.perf_counter() - started
    try:
        _report(args, task.name, task.robot or "PUMA", verdicts, elapsed, task=task)
    except (ValtermError, OSError) as error:
        return fail(error, FAILURE)
    return OK if all(v.passed for v in verdicts) else FAILURE


def _grade_all(task: Any, found: list[Any], limits: Any, jobs: int) -> list[Any]:
    """Every student's verdict, in the order found; in parallel processes when there are several."""
    from valterm.core.grading import grade_student

    one = partial(grade_student, task, limits)
    jobs = min(jobs, len(found))
    if jobs <= 1:
        return [one(path) for path in found]
    with worker_pool(task, jobs) as pool:
        # a few students a message: short programs cost less than the trip to a worker
        return list(pool.map(one, found, chunksize=max(1, len(found) // (4 * jobs))))


def worker_pool(task: Any, jobs: int) -> ProcessPoolExecutor:
    """``jobs`` worker processes started once for the class, each warmed before its first
    student (the collision check loaded, the task's cell read: grading.warm_worker)."""
    from concurrent.futures import ProcessPoolExecutor  # here: multiprocessing is no part of a start

    from valterm.core.grading import warm_worker

    return ProcessPoolExecutor(max_workers=jobs, initializer=warm_worker, initargs=(task,))


def _merge(args: argparse.Namespace) -> int:
    """``grade --merge A.json B.json ...``: one report of shares of a class graded apart."""
    from valterm.core.errors import ValtermError
    from valterm.core.grading import merge_results, read_results

    if args.gradescope:
        return fail("grade: --gradescope is one submission's results, not a merge of a class's", USAGE)
    try:
        files = [read_results(path) for path in [args.task, *args.submissions]]
        verdicts = merge_results(files)
        seconds = max(results.seconds for results in files)  # the shares ran side by side
        _report(args, files[0].task, files[0].robot, verdicts, seconds, f" MERGED FROM {len(files)} FILES")
    except (ValtermError, OSError) as error:
        return fail(error, FAILURE)
    return OK if all(v.passed for v in verdicts) else FAILURE


def _report(args: argparse.Namespace, name: str, robot: str, verdicts: list[Any], elapsed: float,
            merged: str = "", task: Any = None) -> None:
    from valterm.core.files.atomic import write_text_atomic
    from valterm.core.grading import gradescope_results, junit_xml, table_lines

    outputs = []
    if args.json:
        document = {"task": name, "robot": robot, "passed": sum(v.passed for v in verdicts),
                    "failed": sum(not v.passed for v in verdicts), "seconds": round(elapsed, 3),
                    "results": [v.to_json() for v in verdicts]}
        outputs.append((args.json, json.dumps(document, indent=2) + "\n"))
    if args.junit:
        outputs.append((args.junit, junit_xml(name, verdicts)))
    if args.gradescope and task is not None:
        outputs.append((args.gradescope, json.dumps(gradescope_results(task, verdicts[0]), indent=2) + "\n"))
    for target, text in outputs:
        if target != "-":
            write_text_atomic(Path(target).expanduser(), text)
    if any(target == "-" for target, _ in outputs):  # the machine's text alone on standard output
        sys.stdout.write(next(text for target, text in outputs if target == "-"))
        return
    passed = sum(v.passed for v in verdicts)
    lines = table_lines(verdicts)
    lines.append(f"{name}: {len(verdicts)} GRADED, {passed} PASSED, {len(verdicts) - passed} FAILED "
                 f"IN {elapsed:.2f} S ({elapsed / max(1, len(verdicts)):.2f} S A STUDENT){merged}")
    sys.stdout.write("\n".join(lines) + "\n")
