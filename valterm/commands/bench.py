"""``valterm bench [--json]``: the speed figures and the goals they are measured against."""

from __future__ import annotations

import argparse
import json


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("bench", help="measure speed against the project's goals")
    parser.add_argument("--json", action="store_true", help="one JSON object")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from valterm.bench.suite import run_all

    entries = run_all()
    if args.json:
        print(json.dumps(entries, indent=2))
        return 0
    goals = entries.get("goals", {})
    for key, value in entries.items():
        if key in ("goals", "missing"):
            continue
        goal = goals.get(key)
        mark = "" if goal is None else f"   goal {goal['goal']}: {'met' if goal['met'] else 'NOT met'}"
        print(f"{key:32} {value:>14,.2f}{mark}")
    for line in entries.get("missing", []):
        print(f"not measured: {line}")
    return 0
