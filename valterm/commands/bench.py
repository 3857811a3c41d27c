"""``valterm bench [--json]``: the speed figures and the goals they are measured against."""

from __future__ import annotations

import argparse
import json
from typing import Any

from valterm.commands import fail
from valterm.core.errors import ValtermError
from valterm.core.files.atomic import write_text_atomic


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = sub.add_parser("bench", help="measure speed against the project's goals")
    parser.add_argument("--json", action="store_true", help="one JSON object")
    parser.add_argument("--md", action="store_true", help="the goals table in Markdown (docs/PERFORMANCE.md)")
    parser.add_argument("--no-app", action="store_true", help="skip the app under a pseudo-terminal")
    parser.add_argument("--svg", metavar="FILE", help="also write the collision scaling curve to FILE")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from valterm.bench.suite import markdown, run_all

    entries = run_all(app=not args.no_app)
    if args.svg:
        from valterm.bench.plot import scaling_series, scaling_svg

        series = scaling_series(entries)
        if not series:
            return fail(f"no collision figures to plot into {args.svg}")
        try:
            write_text_atomic(args.svg, scaling_svg(series, "Collision check per motion pose: the PUMA among n parts"))
        except ValtermError as error:                    # a link, a folder, a full disk: named
            return fail(f"cannot write the scaling curve: {error}")
    if args.json:
        print(json.dumps(entries, indent=2))
    elif args.md:
        print(markdown(entries))
    else:
        _print_figures(entries)
    unmet = [key for key, goal in entries.get("goals", {}).items() if goal["met"] is False]
    if unmet:                                             # measured and missed: a failed check
        return fail(f"{len(unmet)} goal(s) not met: {', '.join(unmet)}")
    return 0


def _print_figures(entries: dict[str, Any]) -> None:
    goals = entries.get("goals", {})
    for key, value in entries.items():
        if key in ("goals", "missing", "machine", "notes"):
            continue
        goal = goals.get(key)
        mark = "" if goal is None else f"   goal {goal['goal']}: {'met' if goal['met'] else 'NOT met'}"
        print(f"{key:32} {value:>14,.2f}{mark}")
    for line in entries.get("missing", []):
        print(f"not measured: {line}")
    for line in entries.get("notes", []):
        print(f"note: {line}")
