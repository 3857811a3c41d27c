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
from valterm.core.val import dialects


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    parser = subparsers.add_parser("check", help="syntax-check VAL-II programs (.DAT)")
    parser.add_argument("files", nargs="+", metavar="FILE.DAT",
                        help="a path (.DAT, or a V+ file .v2/.pg with .PROGRAM blocks), or a program name in the workspace")
    parser.add_argument("--dialect", choices=dialects.NAMES, default=None,
                        help="the language to check against (default: 1985 for .DAT, v+ for .v2/.pg)")
    parser.set_defaults(func=run)


def read_programs(path: Path) -> list:  # type: ignore[type-arg]
    """The programs of a file: one for NAME.DAT, every .PROGRAM block of a V+ file."""
    return read_checked(path)[0]


def read_checked(path: Path) -> tuple[list, list[str]]:  # type: ignore[type-arg]
    """The programs of a file, and what is wrong outside their steps (a V+ file's bad
    header or data line: "FILE:LINE: reason"), which does not stop the rest being checked."""
    from valterm.core.files.programs import read_program
    from valterm.core.files.vplus import EXTENSIONS, read_vplus_file

    if path.suffix.upper() in EXTENSIONS:
        found = read_vplus_file(path)
        problems = [b.problem for b in found.blocks if b.problem] + found.data.problems
        return [block.program for block in found.blocks], problems
    return [read_program(path)], []


def find_program(argument: str, workspace_root: str | None) -> tuple[Path, Callable[[str], bool]]:
    """The program file and a test for the programs it may CALL (same folder, or the workspace)."""
    from valterm.core.workspace import Workspace

    given = Path(argument).expanduser()
    if given.is_file():
        return given, Workspace(given.resolve().parent).program_test()  # CALLs: the same folder
    looks_like_path = any(sep in argument for sep in ("/", "\\")) or given.suffix.upper() not in ("", ".DAT")
    if looks_like_path and not _dotted(argument):
        raise FileNotFoundError(f"{argument}: no such program file")
    workspace = Workspace.open(workspace_root)
    path = workspace.path(argument, "DAT") if not _dotted(argument) else None
    if path is None or not path.is_file():
        found = workspace.vplus_source(argument)  # a program of a workspace V+ file: check the file
        if found is not None:
            return found[1], workspace.program_test()
    if path is None:  # a dotted name that is no program of the workspace: perhaps a file
        raise FileNotFoundError(f"{argument}: no such program file (and no V+ file of the workspace has it)")
    return path, workspace.program_test()


def _dotted(name: str) -> bool:
    from valterm.core.files.vplus import is_dotted_name

    return is_dotted_name(name)


def run(args: argparse.Namespace) -> int:
    from valterm.core.val.checker import check_program
    from valterm.core.workspace import WorkspaceError

    status = OK
    dialect = getattr(args, "dialect", None)
    for argument in args.files:
        try:
            path, exists = find_program(argument, getattr(args, "workspace", None))
            programs, problems = read_checked(path)
        except (FileFormatError, WorkspaceError, FileNotFoundError, OSError) as error:
            say(error)
            status = FAILURE
            continue
        for problem in problems:
            print(problem)
            status = FAILURE
        vplus_file = path.suffix.upper() in (".V2", ".PG")
        in_file = {program.name for program in programs}

        def known(name: str, in_file: set[str] = in_file, exists: Callable[[str], bool] = exists) -> bool:
            return name in in_file or exists(name)
        for program in programs:
            try:
                report = check_program(program, program_exists=known, dialect=dialect)
            except WorkspaceError as error:  # a CALLed program that links outside the workspace
                say(f"{path.name}: {error}")
                status = FAILURE
                continue
            for diagnostic in report.diagnostics:
                # a V+ file holds several programs: say which file and line as well
                print(f"{path.name}:{diagnostic.line}: {diagnostic}" if vplus_file and diagnostic.line else diagnostic)
            print(f"{report.summary()}  [{report.against}]")
            if not report.ok:
                status = FAILURE
    return status
