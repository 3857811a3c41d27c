"""The Editor of VAL-II SIMULATOR (EVS), Chapter 5 and Fig. 5-1, as a plain class.

``ProgramEditor(workspace, name)`` opens NAME.DAT through DATFILER.DAT (§5.1): an old
program is loaded; a new one is reported (``INPUT FILE NAME.DAT DOES NOT EXIST``), started
empty and its name added to DATFILER.DAT. C continues with the next step, D deletes a step,
I inserts one; steps renumber themselves (§5.2). Every entered line is syntax-checked and a
bad one is rejected with the checker's message. S saves (atomically), E exits, and a wrong
key says so and saves at once (§5.2).

Nothing typed is lost: each accepted change is written at once to a journal file beside the
program (``NAME.~DAT``, which LISTF does not list); a later open of the same program
recovers it. Saving (or discarding) removes the journal.

Two sessions on one workspace: the journal is the first editor's (it holds the lock file
``.NAME.~DAT.lock`` while it is open); a second editor of the same program neither recovers
nor removes it, and keeps its own changes unjournalled until it saves. A save checks that
NAME.DAT is still what this editor read;
when another session saved it meanwhile, ``save()`` raises FileChanged (nothing written) and
the UI asks: ``save(overwrite=True)``, ``reload()`` (take the other session's program) or
``save_as(NAME)``.

No UI import here: the Textual editor screen and the tests drive this class.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

from valterm.core.errors import ValtermError
from valterm.core.files._text import read_text
from valterm.core.files.atomic import claim, release, text_stamp, write_text_atomic
from valterm.core.files.errors import FileFormatError
from valterm.core.files.programs import (
    LABEL_COLUMNS,
    MAX_LINE,
    Program,
    ProgramLine,
    format_program,
    format_step,
    parse_program,
    split_label,
)
from valterm.core.val.checker import check_statement
from valterm.core.workspace import Workspace

JOURNAL_EXT = "~DAT"
JOURNAL_HEAD = "; VALTERM JOURNAL OF "
JOURNAL_BASE = " CHANGING "  # then the stamp of NAME.DAT the changes were made to

# Fig. 5-1 / Fig. C-8, as the thesis prints it.
EDITOR_MENU = (
    "EDITOR COMMANDS",
    "",
    "LEGAL EDITING COMMANDS",
    "",
    "EDIT   : INVOKES EDIT MODE",
    "CREATE : INVOKES CREATION MODE",
    "INSERT : ALLOWS FOR LINE INSERTION",
    "DELETE : ALLOWS FOR LINE DELETION",
    "SAVE   : SAVES THE FILE",
    "EXIT   : ENDS THE EDIT SESSION",
    "",
    'TYPE "EDIT" AND THEN PROGRAM NAME TO START EDIT SESSION',
)

EDITOR_KEYS = "ECIDSX"  # E doubles as EDIT (no program yet) and EXIT; X is not a thesis key

_EDIT_COMMAND = re.compile(r"^\s*(?:EDIT\b\s*)?(.*?)\s*$", re.I)

# A checker returns None for a good statement or the reason it is rejected.
Checker = Callable[[str], "str | None"]


class EditorError(ValtermError):
    """A request the editor refuses; the message is shown to the user as is."""


def expand_tab(typed: str) -> str:
    """A typed TAB jumps to column 5, where the statement starts (columns 1-4: the label)."""
    if "\t" not in typed:
        return typed
    head, _, tail = typed.partition("\t")
    head = head[:LABEL_COLUMNS].ljust(LABEL_COLUMNS)
    return head + expand_tab(tail).lstrip(" ")


def program_name(typed: str) -> str:
    """``EDIT TEST.DAT`` / ``TEST.DAT`` / ``test`` -> ``TEST`` (the name rules are the workspace's)."""
    match = _EDIT_COMMAND.match(typed)
    name = (match.group(1) if match else typed).strip().upper()
    if not name:
        raise EditorError('TYPE "EDIT" AND THEN PROGRAM NAME')
    return name.removesuffix(".DAT")


class ProgramEditor:
    """One edit session on one program (Chapter 5)."""

    def __init__(self, workspace: Workspace, name: str, checker: Checker | None = None) -> None:
        self.workspace = workspace
        self.check: Checker = checker or check_statement
        self.messages: list[str] = []
        # why this program cannot be changed here ("" when it can): a V+ program of a .V2/.PG
        # file is shown, not edited, since saving one block would rewrite the others' file
        self.read_only = ""
        typed = program_name(name)
        found = workspace.vplus_source(typed)
        if found is not None:
            self._open_vplus(*found)
            return
        self.name = workspace._program_name(typed)  # WorkspaceError for a bad name
        self.path: Path = workspace.path(self.name, "DAT")
        self.journal_path: Path = workspace.path(self.name, JOURNAL_EXT)  # refused if it links outside
        self.new = False
        self.recovered = False
        self.dirty = False  # changes not yet saved to NAME.DAT
        self.stamp = ""  # NAME.DAT as read ("" none): a save checks it is still so
        self._journal_lock: int | None = self._claim_journal()
        self._journal_base: str | None = None
        self.program = self._open()

    # -- opening (§5.1) ----------------------------------------------------------
    def _open_vplus(self, program: Program, source: Path) -> None:
        self.name, self.path, self.journal_path = program.name, source, source  # no journal is kept
        self.new = self.recovered = self.dirty = False
        self.stamp = ""
        self._journal_lock = -1
        self.program = program
        self.read_only = (f"{program.name} IS A V+ PROGRAM OF {source.name}: SHOWN HERE, NOT CHANGED "
                          f"(EDIT {source.name} ITSELF)")
        self.messages.append(self.read_only)

    def _open(self) -> Program:
        listed = self.name in self.workspace.programs_directory()
        program: Program | None = None
        self.stamp = self.workspace.stamp(self.name, "DAT")  # before reading: a change meanwhile asks
        if self.path.is_file():
            try:
                program = self.workspace.read_program(self.name)
            except FileFormatError as error:
                self.messages.append(f"{error}: STARTING FROM THE JOURNAL OR AN EMPTY PROGRAM")
        if program is None:
            self.new = True
            self.messages.append(f"INPUT FILE {self.name}.DAT DOES NOT EXIST")
            program = Program(self.name)
        if not listed:
            # §5.1: a new program's name is added to the list and DATFILER.DAT updated
            self.workspace.add_program(self.name)
        if self._journal_lock is None:
            self.messages.append(f"{self.name}.DAT IS OPEN IN ANOTHER SESSION: ITS UNSAVED CHANGES STAY ITS OWN; "
                                 "YOURS ARE KEPT WHEN YOU SAVE")
            return program
        recovered = self._read_journal()
        if recovered is not None:
            # the journal's changes were made to NAME.DAT as it was then: a save asks if it changed since
            self.stamp = self._journal_base if self._journal_base is not None else self.stamp
            self.recovered = True
            self.dirty = True
            self.messages.append(f"RECOVERED UNSAVED EDITS OF {self.name}.DAT ({len(recovered.steps)} STEPS)")
            return recovered
        return program

    def _read_journal(self) -> Program | None:
        if not self.journal_path.is_file():
            return None
        try:
            text = read_text(self.journal_path, "journal")  # the one read path (no FIFO, no device)
        except FileFormatError:
            return None
        lines = text.splitlines()
        if not lines or not lines[0].startswith(JOURNAL_HEAD):
            return None
        _, at, base = lines[0].partition(JOURNAL_BASE)
        self._journal_base = base.strip() if at else None
        body = "\n".join(lines[1:])
        if not body.strip():
            return Program(self.name)
        try:
            return parse_program(body, self.name, self.journal_path)
        except FileFormatError:
            return None

    def _claim_journal(self) -> int | None:
        """The journal's lock file: the descriptor that holds it, None when another session does."""
        return claim(self.workspace.root / f".{self.journal_path.name}.lock")

    def close(self) -> None:
        """The editor is left: another session may take the journal over."""
        release(self._journal_lock)
        self._journal_lock = -1 if self.read_only else None

    def __del__(self) -> None:  # an editor dropped without close() lets the journal go too
        try:
            release(getattr(self, "_journal_lock", None))
        except (TypeError, AttributeError):  # at interpreter exit the module may be gone already
            pass

    def _write_journal(self) -> None:
        """Every accepted change reaches the disk at once (closing the app mid-edit loses nothing)."""
        self.dirty = True
        if self._journal_lock is None:
            return  # another session's journal: not overwritten
        head = JOURNAL_HEAD + self.name + JOURNAL_BASE + self.stamp  # the file the changes were made to
        text = head + "\n" + "".join(format_step(s) + "\n" for s in self.program.steps)
        write_text_atomic(self.journal_path, text)

    # -- the listing ----------------------------------------------------------------
    @property
    def steps(self) -> list[ProgramLine]:
        return self.program.steps

    @property
    def next_step(self) -> int:
        return len(self.program.steps) + 1

    def prompt(self, step: int | None = None) -> str:
        """The step prompt, ``S. 5>``."""
        return f"S. {self.next_step if step is None else step}>"

    def listing(self) -> list[str]:
        """The program as shown after each change: step number, label columns, statement."""
        return [f"{number:>4}. {format_step(step)}" for number, step in enumerate(self.program.steps, start=1)]

    # -- entering lines (§5.1, §5.2) -------------------------------------------------
    def parse_line(self, typed: str) -> ProgramLine:
        """The step a typed line makes, or EditorError with the reason it is rejected."""
        line = expand_tab(typed).rstrip("\r\n")
        if not line.strip():
            raise EditorError("EMPTY LINE: TYPE A VAL-II STATEMENT")
        if len(line) > MAX_LINE:
            raise EditorError(f"LINE TOO LONG ({len(line)} CHARACTERS, AT MOST {MAX_LINE})")
        try:
            label, statement = split_label(line)
        except ValueError as error:
            raise EditorError(str(error).upper()) from None
        if statement and not statement.startswith(";"):
            reason = self.check(statement)
            if reason:
                raise EditorError(reason)
        if label is not None and self.program.find_label(label) is not None:
            raise EditorError(f"STEP LABEL {label} IS ALREADY USED (STEP {self.program.find_label(label)})")
        return ProgramLine(label, statement)

    def append(self, typed: str) -> int:
        """C: the next step; returns its step number."""
        return self.insert(self.next_step, typed)

    def insert(self, number: int, typed: str) -> int:
        """I: a new step ``number``; the steps from there on move down one."""
        if self.read_only:
            raise EditorError(self.read_only)
        if not 1 <= number <= self.next_step:
            raise EditorError(f"NO STEP {number}: STEPS ARE 1 TO {self.next_step}")
        step = self.parse_line(typed)
        self.program.steps.insert(number - 1, step)
        self._write_journal()
        return number

    def delete(self, number: int) -> ProgramLine:
        """D: remove step ``number``; the later steps move up one."""
        if self.read_only:
            raise EditorError(self.read_only)
        if not 1 <= number <= len(self.program.steps):
            if not self.program.steps:
                raise EditorError(f"{self.name} HAS NO STEPS TO DELETE")
            raise EditorError(f"NO STEP {number}: STEPS ARE 1 TO {len(self.program.steps)}")
        removed = self.program.steps.pop(number - 1)
        self._write_journal()
        return removed

    # -- saving and leaving --------------------------------------------------------
    def save(self, overwrite: bool = False) -> Path:
        """S: write NAME.DAT atomically, list it in DATFILER.DAT, drop the journal.

        FileChanged (nothing written) when NAME.DAT changed on disk since this editor read or
        saved it, unless ``overwrite``."""
        if self.read_only:
            raise EditorError(self.read_only)
        path = self.workspace.write_program(self.program, self.name, None if overwrite else self.stamp)
        self.stamp = text_stamp(format_program(self.program))
        self.path = path
        self.new = False
        self.dirty = False
        self._drop_journal()
        return path

    def reload(self) -> Program:
        """Take NAME.DAT as it is on disk now (another session's save): this editor's unsaved
        changes and its journal go."""
        if self.read_only:
            raise EditorError(self.read_only)
        self.stamp = self.workspace.stamp(self.name, "DAT")
        self.program = self.workspace.read_program(self.name) if self.path.is_file() else Program(self.name)
        self.new = not self.path.is_file()
        self.dirty = False
        self._drop_journal()
        return self.program

    def save_as(self, name: str) -> Path:
        """Save the program under a new name (one no file has) and go on editing that one;
        the program it was opened as stays as the other session saved it."""
        if self.read_only:
            raise EditorError(self.read_only)
        stem = self.workspace._program_name(program_name(name))  # WorkspaceError for a bad name
        if self.workspace.path(stem, "DAT").exists() or self.workspace.vplus_source(stem) is not None:
            raise EditorError(f"{stem}.DAT EXISTS: GIVE A NEW NAME")
        self._drop_journal()
        release(self._journal_lock)
        self.name = stem
        self.path = self.workspace.path(stem, "DAT")
        self.journal_path = self.workspace.path(stem, JOURNAL_EXT)
        self._journal_lock = self._claim_journal()
        self.program = replace(self.program, name=stem, steps=list(self.program.steps))
        self.stamp = ""  # no file yet: a file made meanwhile is a change too
        return self.save()

    def discard(self) -> None:
        """Leave without saving: the journal goes, NAME.DAT stays as it was."""
        if self.read_only:
            return  # a V+ program: nothing was changed, its file is no journal
        self._drop_journal()
        self.dirty = False

    def wrong_key(self, key: str) -> str:
        """§5.2: a wrong key is named to the user and the modified file saved at once."""
        shown = key if key.isprintable() and key.strip() else repr(key)
        said = f"'{shown.upper()}' IS NOT AN EDITOR COMMAND"
        if not self.dirty:
            return f"{said}; {self.name}.DAT IS UNCHANGED"
        return f"{said}; {self.save().name} SAVED"

    def _drop_journal(self) -> None:
        if self.read_only or self._journal_lock is None:
            return
        try:
            os.unlink(self.journal_path)
        except FileNotFoundError:
            pass
