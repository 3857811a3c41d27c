"""``valterm check FILE.DAT ...``: the VAL-II syntax checker on program files.

FILE is a path or a program name in the workspace. Every bad step is reported as
``PROGRAM step N: reason`` (warnings too: GOTO to a missing label, CALL of a missing
program). Exit 0 with a summary when all is well, 1 when anything is wrong or a file
cannot be read (``valterm: FILE:LINE: reason`` on stderr).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

from valterm.commands import FAILURE, OK, say
from valterm.core.files.errors import FileFormatError


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("check", help="syntax-check VAL-II programs (.DAT)")
    parser.add_argument("files", nargs="+", metavar="FILE.DAT", help="a path, or a program name in the workspace")
    parser.set_defaults(func=run)


def find_program(argument: str, workspace_root: str | None) -> tuple[Path, Callable[[str], bool]]:
    """The program file and a test for the programs it may CALL (same folder, or the workspace)."""
    given = Path(argument).expanduser()
    if given.is_file():
        folder = given.resolve().parent
        names = {p.name.upper() for p in folder.iterdir() if p.is_file()}
        return given, lambda name: f"{name.upper()}.DAT" in names
    looks_like_path = any(sep in argument for sep in ("/", "\\")) or given.suffix.upper() not in ("", ".DAT")
    if looks_like_path:
        raise FileNotFoundError(f"{argument}: no such program file")
    from valterm.core.workspace import Workspace

    workspace = Workspace.open(workspace_root)
    return workspace.path(argument, "DAT"), lambda name: workspace.exists(name, "DAT")


def run(args: argparse.Namespace) -> int:
    from valterm.core.files.programs import read_program
    from valterm.core.val.checker import check_program
    from valterm.core.workspace import WorkspaceError

    status = OK
    for argument in args.files:
        try:
            path, exists = find_program(argument, getattr(args, "workspace", None))
            program = read_program(path)
        except (FileFormatError, WorkspaceError, FileNotFoundError, OSError) as error:
            say(error)
            status = FAILURE
            continue
        report = check_program(program, program_exists=exists)
        for diagnostic in report.diagnostics:
            print(diagnostic)
        print(report.summary())
        if not report.ok:
            status = FAILURE
    return status
