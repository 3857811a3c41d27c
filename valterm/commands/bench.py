"""``valterm bench [--json]``: the speed figures and the goals they are measured against."""

from __future__ import annotations

import argparse
import json


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("bench", help="measure speed against the project's goals")
    parser.add_argument("--json", action="store_true", help="one JSON object")
    parser.add_argument("--md", action="store_true", help="the goals table in Markdown (docs/PERFORMANCE.md)")
    parser.add_argument("--no-app", action="store_true", help="skip the app under a pseudo-terminal")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from valterm.bench.suite import markdown, run_all

    entries = run_all(app=not args.no_app)
    if args.json:
        print(json.dumps(entries, indent=2))
        return 0
    if args.md:
        print(markdown(entries))
        return 0
    goals = entries.get("goals", {})
    for key, value in entries.items():
        if key in ("goals", "missing", "machine"):
            continue
        goal = goals.get(key)
        mark = "" if goal is None else f"   goal {goal['goal']}: {'met' if goal['met'] else 'NOT met'}"
        print(f"{key:32} {value:>14,.2f}{mark}")
    for line in entries.get("missing", []):
        print(f"not measured: {line}")
    return 0
