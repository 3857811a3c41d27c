"""EDIT mode (Chapter 5, Figs. 5-1 and C-8): the editor menu, always shown, and the program.

First the ``EDIT NAME`` line (``EDIT TEST.DAT`` or just ``TEST``); then single keys:
C continue with the next step, I insert, D delete, S save, E exit. A space, a TAB or a
digit in the menu starts the next step too, label columns first. Any other key is a wrong
key: it is named and the program saved (§5.2). All the work is done by ``valterm.core.editor``.

The keyboard model (valterm.ui.keymap): after an accepted step the line stays open with the
next ``S. n>`` prompt, so a program typed line after line never has a line taken as menu
keys; ESC (or RETURN on an empty line) closes the line and returns to the editor menu. ESC
at the menu is E_XIT. A new program never saved is taken off DATFILER.DAT when the editor
is left.

A save that finds NAME.DAT changed on disk (another session saved it) asks, in the one
question screen (valterm.ui.screens.changed): overwrite, reload or save as.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from enum import StrEnum
from typing import TYPE_CHECKING, ClassVar

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical, VerticalScroll
from textual.events import Key, Resize
from textual.widgets import Input, Static

from valterm.core.editor import EDITOR_MENU, EditorError, ProgramEditor
from valterm.core.errors import ValtermError
from valterm.core.files.errors import FileChanged
from valterm.core.files.programs import LABEL_COLUMNS
from valterm.ui import keymap, legends
from valterm.ui.screens.keyed import KeyedScreen
from valterm.ui.widgets.prompt import typed_after
from valterm.ui.widgets.status import StatusLine

if TYPE_CHECKING:  # annotations only
    from valterm.core.workspace import Workspace

NARROW = 120  # columns below which the menu box is left out (80x24: the listing needs them)
RULER = "LBL STATEMENT (COLUMNS 1-4: STEP LABEL, TAB: TO COLUMN 5)"


class StepInput(Input):
    """A program line: TAB jumps to column 5 instead of leaving the field."""

    BINDINGS = [Binding("tab", "column_five", "Column 5", show=False, id="editor.tab")]

    def action_column_five(self) -> None:
        if len(self.value) < LABEL_COLUMNS:
            self.value = self.value.ljust(LABEL_COLUMNS)
        else:
            self.insert_text_at_cursor(" ")
        self.cursor_position = len(self.value)


# modes in which the step field takes the keys (typed ahead before it has focus too)
class EditorMode(StrEnum):
    """The editor's one state value: where its keys go."""

    NAME = "name"  # the EDIT NAME line
    MENU = "menu"  # C, I, D, S, E
    LINE = "line"  # the next step
    DELETE = "delete"  # the step number to delete
    INSERT = "insert"  # the step number to insert at
    INSERT_LINE = "insert-line"  # the step inserted
    SAVE = "save?"  # SAVE THE CHANGES (Y/N) ?


TEXT_MODES = frozenset({EditorMode.NAME, EditorMode.LINE, EditorMode.DELETE, EditorMode.INSERT,
                        EditorMode.INSERT_LINE})



# the editor menu's keys as they are bound now (ui/legends.fill)
MENU_KEYS = ("{editor.create} CONTINUE  {editor.insert} INSERT  {editor.delete} DELETE  {editor.save} SAVE  "
             "{editor.exit} EXIT  {screen.help} HELP")
STEP_END = "({editor.cancel} OR AN EMPTY LINE: EDITOR MENU)"

class EditorScreen(KeyedScreen[None]):
    """The Editor of VAL-II SIMULATOR (EVS)."""

    AUTO_FOCUS = None
    DEFAULT_CSS = """
    EditorScreen #editor-menu { width: 60; padding: 0 1; border: round $primary; height: auto; }
    EditorScreen #editor-right { width: 1fr; }
    EditorScreen #editor-title { padding: 0 1; text-style: bold; }
    EditorScreen #editor-scroll { height: 1fr; border: round $secondary; }
    EditorScreen #editor-listing { padding: 0 1; }
    EditorScreen #editor-message { height: auto; min-height: 1; padding: 0 1; color: $warning; }
    EditorScreen #editor-prompt-row { height: 3; }
    EditorScreen #editor-prompt { width: auto; min-width: 8; padding: 1 1 0 1; }
    EditorScreen #editor-line { width: 1fr; }
    EditorScreen #editor-prompt-row.hidden { display: none; }
    EditorScreen.-narrow #editor-menu { display: none; }
    """
    BINDINGS = [
        Binding("c,C", "create", "Continue", id="editor.create"),
        Binding("i,I", "insert", "Insert", id="editor.insert"),
        Binding("d,D", "delete", "Delete", id="editor.delete"),
        Binding("s,S", "save", "Save", id="editor.save"),
        Binding("e,E", "exit", "Exit", id="editor.exit"),
        Binding("escape", "cancel", "Cancel", id="editor.cancel"),
        Binding("y,Y", "save_answer('Y')", "Save the changes", show=False, id="editor.save_yes"),
        Binding("n,N", "save_answer('N')", "Leave them unsaved", show=False, id="editor.save_no"),
    ]
    # which keys work in which state: the one place (KeyedScreen.check_action reads it)
    STATES: ClassVar[Mapping[str, frozenset[str]]] = {
        **{action: frozenset({EditorMode.MENU}) for action in ("create", "insert", "delete", "save", "exit")},
        "save_answer": frozenset({EditorMode.SAVE}),
    }

    def __init__(self, workspace: Workspace | None = None, name: str = "") -> None:
        super().__init__()
        self._workspace = workspace
        self.first_name = name
        self.editor: ProgramEditor | None = None
        self.mode = EditorMode.NAME
        self.insert_at = 0

    # -- layout ---------------------------------------------------------------------
    def compose(self) -> ComposeResult:
        with Horizontal():
            yield Static("\n".join(EDITOR_MENU), id="editor-menu")
            with Vertical(id="editor-right"):
                yield Static("", id="editor-title")
                with VerticalScroll(id="editor-scroll"):
                    yield Static("", id="editor-listing")
        yield Static("", id="editor-message")
        with Horizontal(id="editor-prompt-row"):
            yield Static("EDIT", id="editor-prompt")
            yield StepInput(id="editor-line", placeholder="TEST.DAT")
        yield StatusLine(id="status")

    def on_resize(self, event: Resize) -> None:
        self._fit_width(event.size.width)

    def _fit_width(self, width: int) -> None:
        """Narrower than NARROW columns the menu box goes (the key line under the listing
        says the keys): the listing gets the width, no step wraps mid-command."""
        self.set_class(width < NARROW, "-narrow")

    def on_mount(self) -> None:
        self._fit_width(self.app.size.width)
        if self.first_name:
            self.open_program(self.first_name)
        else:
            self._prompt("name", "EDIT", "PROGRAM NAME, e.g. TEST.DAT")

    @property
    def workspace(self) -> Workspace:
        if self._workspace is None:
            session = self.app.session  # the editor also runs over a bare workspace (tests' hosts)
            assert session is not None, "the editor without a workspace"
            self._workspace = session.workspace
        return self._workspace

    # -- what the screen shows (tests read these) --------------------------------------
    @property
    def message(self) -> str:
        return str(self.query_one("#editor-message", Static).content)

    @property
    def listing(self) -> str:
        return str(self.query_one("#editor-listing", Static).content)

    @property
    def prompt(self) -> str:
        return str(self.query_one("#editor-prompt", Static).content)

    def say(self, *lines: str) -> None:
        self.query_one("#editor-message", Static).update("\n".join(lines))
        self.query_one("#status", StatusLine).refresh()

    def _prompt(self, mode: str, prompt: str, placeholder: str = "", start: str = "") -> None:
        self.mode = EditorMode(mode)
        self.query_one("#editor-prompt", Static).update(prompt)
        self.query_one("#editor-prompt-row").remove_class("hidden")
        field = self.query_one("#editor-line", StepInput)
        field.placeholder = placeholder
        field.value = start
        field.cursor_position = len(start)
        field.focus()

    def _menu(self) -> None:
        self.mode = EditorMode.MENU
        self.query_one("#editor-prompt-row").add_class("hidden")
        self.set_focus(None)

    def _refresh_listing(self, changed: int | None = None) -> None:
        editor = self.editor
        if editor is None:
            return
        state = " (NEW)" if editor.new else ""
        state += " (NOT SAVED)" if editor.dirty else ""
        shown = f"{editor.name} ({editor.path.name}, READ ONLY)" if editor.read_only else f"{editor.name}.DAT"
        self.query_one("#editor-title", Static).update(f"EDIT {shown}{state}")
        lines = editor.listing() or [legends.fill(self, "(NO STEPS YET: PRESS {editor.create} TO TYPE THE FIRST STEP)")]
        self.query_one("#editor-listing", Static).update("\n".join(lines))
        scroll = self.query_one("#editor-scroll", VerticalScroll)
        if changed is None or changed >= len(editor.steps):
            scroll.call_after_refresh(scroll.scroll_end, animate=False)
        else:
            scroll.call_after_refresh(scroll.scroll_to, y=max(0, changed - 3), animate=False)

    # -- opening --------------------------------------------------------------------
    def open_program(self, typed: str) -> bool:
        try:
            self.editor = ProgramEditor(self.workspace, typed)
        except ValtermError as error:
            self.say(str(error).upper())
            self._prompt("name", "EDIT", "PROGRAM NAME, e.g. TEST.DAT")
            return False
        self.say(*(self.editor.messages or [f"{self.editor.name}.DAT: {len(self.editor.steps)} STEPS"]),
                 legends.fill(self, MENU_KEYS))
        self._refresh_listing()
        self._menu()
        return True

    # -- keys: the one key path (KeyedScreen.on_key) -----------------------------------------
    @property
    def key_state(self) -> str:
        return self.mode

    def line_taking_keys(self) -> StepInput | None:
        return self.query_one("#editor-line", StepInput) if self.mode in TEXT_MODES else None

    def other_key(self, event: Key) -> bool:
        """The menu: TAB, a space or a digit starts the next step (label columns first)."""
        char = event.character or ""
        if self.mode == EditorMode.SAVE:
            if not keymap.is_silent(event) and event.key != "ctrl+c":
                self.say(f"SAVE THE CHANGES TO {self.editor.name}.DAT (Y/N) ?",  # type: ignore[union-attr]
                         keymap.wrong_answer(event, legends.keys_of(self, "editor.save_yes", "editor.save_no"),
                                             legends.key_for(self, "cancel", "ESC")))
            return True
        if self.mode != EditorMode.MENU:
            return False
        if event.key == "tab":
            self._next_line(" " * LABEL_COLUMNS)
        elif char == " " or char.isdigit():
            self._next_line(char)
        else:
            return False
        return True

    def say_wrong_key(self, text: str) -> None:
        self.say(text)

    def wrong_key(self, event: Key) -> None:
        """A wrong key at the editor's menu is named and the program saved (§5.2)."""
        if self.editor is None or self.mode != EditorMode.MENU:
            super().wrong_key(event)
            return
        try:
            self.say(self.editor.wrong_key(keymap.key_name(event)), legends.help_hint(self))
        except FileChanged:  # §5.2 saves at once: another session saved it meanwhile
            self.ask_changed()
        self._refresh_listing()

    def action_save_answer(self, answer: str) -> None:
        self._leave(save=answer == "Y")

    def action_create(self) -> None:
        self._next_line("")

    def _next_line(self, start: str) -> None:
        assert self.editor is not None
        self._prompt("line", self.editor.prompt(), "", start)

    def action_insert(self) -> None:
        self._prompt("insert", "INSERT AT STEP NO.", "STEP NUMBER")

    def action_delete(self) -> None:
        self._prompt("delete", "DELETE STEP NO.", "STEP NUMBER")

    def action_save(self) -> None:
        assert self.editor is not None
        try:
            path = self.editor.save()
        except EditorError as error:  # a V+ program of a .V2 file is shown, not saved
            self.say(f"REJECTED: {error}")
            return
        except FileChanged:
            self.ask_changed()
            return
        self.say(f"{path.name} SAVED ({len(self.editor.steps)} STEPS)")
        self._refresh_listing()

    def ask_changed(self, then: Callable[[], None] | None = None) -> None:
        """NAME.DAT changed on disk since it was read: overwrite, reload or save as (``then``
        runs after a save or a reload, e.g. leaving the editor)."""
        from valterm.ui.screens.changed import FileChangedScreen

        editor = self.editor
        assert editor is not None
        self.say(f"{editor.name}.DAT CHANGED ON DISK: NOT SAVED")

        def answered(answer: tuple[str, str] | None) -> None:
            if answer is None:
                self.say(f"{editor.name}.DAT NOT SAVED: YOUR CHANGES ARE KEPT HERE (S SAVES AGAIN)")
                return
            what, name = answer
            try:
                if what == "overwrite":
                    said = f"{editor.save(overwrite=True).name} SAVED OVER THE OTHER SESSION'S"
                elif what == "reload":
                    editor.reload()
                    said = f"{editor.name}.DAT RELOADED AS THE OTHER SESSION SAVED IT"
                else:
                    said = f"{editor.save_as(name).name} SAVED; NOW EDITING {editor.name}"
            except FileChanged:
                self.ask_changed(then)
                return
            except ValtermError as error:  # a bad or used name: say so, ask again
                self.ask_changed(then)
                self.say(f"REJECTED: {error}")
                return
            self.say(said)
            self._refresh_listing()
            if then is not None:
                then()

        self.app.push_screen(FileChangedScreen(f"{editor.name}.DAT", "program"), answered)

    def action_exit(self) -> None:
        if self.editor is not None and self.editor.dirty:
            self.mode = EditorMode.SAVE
            self.say(f"SAVE THE CHANGES TO {self.editor.name}.DAT (Y/N) ?")
            return
        self._unlist_if_never_saved()
        self.close()

    def _leave(self, save: bool) -> None:
        assert self.editor is not None
        if save:
            try:
                self.editor.save()
            except FileChanged:
                self._menu()
                self.ask_changed(then=self.close)
                return
        else:
            self.editor.discard()
            self._unlist_if_never_saved()
        self.close()

    def _unlist_if_never_saved(self) -> None:
        """A program opened new and never saved leaves DATFILER.DAT (LISTF shows no ghosts)."""
        from valterm.core.files.datfiler import remove_program_name

        editor = self.editor
        if editor is None or not editor.new or editor.path.exists():
            return
        remove_program_name(self.workspace.path("DATFILER", "DAT"), editor.name)

    def action_help(self) -> None:
        from valterm.ui.screens.help import HelpScreen

        self.app.push_screen(HelpScreen(screen="EDITOR", keys=legends.legend(self)))

    def action_cancel(self) -> None:
        """ESC: the open line closes (editor menu); at the menu ESC is E_XIT."""
        if self.mode in ("line", "insert", "delete", "insert-line") and self.editor is not None:
            self.say(legends.fill(self, f"LINE CLOSED: {MENU_KEYS}"))
            self._menu()
        elif self.mode == "save?":
            self._menu()
            self.say("")
        elif self.mode == "menu":
            self.action_exit()
        elif self.editor is None:
            self.close()

    # -- lines typed ----------------------------------------------------------------------
    def on_input_submitted(self, event: Input.Submitted) -> None:
        event.stop()
        typed = event.value
        after = typed_after(self.query_one("#editor-line", StepInput), typed)  # typed since RETURN
        if self.mode == "name":
            self.open_program(typed)
            return
        editor = self.editor
        assert editor is not None
        read = ""
        if self.mode in ("line", "insert-line"):
            typed, read = self._read_as_1985(typed)
        try:
            if self.mode == "line":
                if not typed.strip():
                    self.action_cancel()  # RETURN on an empty line: back to the menu
                    return
                number = editor.append(typed)
                self.say(legends.fill(self, f"STEP {number} ACCEPTED{read} {STEP_END}"))
                self._refresh_listing(number)
                if getattr(self.app, "keys_1985", False):
                    self._menu()  # 1985 (Fig. C-8): the menu; a space or a digit starts the next step
                else:
                    self._next_line(after)  # the line stays open: typed lines are never menu keys
            elif self.mode == "delete":
                number = self._number(typed)
                removed = editor.delete(number)
                self.say(f"STEP {number} DELETED: {removed.text}")
                self._refresh_listing(number)
                self._menu()
            elif self.mode == "insert":
                number = self._number(typed)
                if not 1 <= number <= editor.next_step:
                    raise EditorError(f"NO STEP {number}: STEPS ARE 1 TO {editor.next_step}")
                self.insert_at = number
                self._prompt("insert-line", editor.prompt(number))
            elif self.mode == "insert-line":
                if not typed.strip():
                    self.action_cancel()
                    return
                number = editor.insert(self.insert_at, typed)
                self.say(legends.fill(self, f"STEP {number} INSERTED{read} {STEP_END}"))
                self._refresh_listing(number)
                self.insert_at = number + 1  # the next line goes in after it
                if getattr(self.app, "keys_1985", False):
                    self._menu()  # 1985: one step a time, then the menu
                else:
                    self._prompt("insert-line", editor.prompt(self.insert_at), "", after)
        except ValtermError as error:
            if getattr(self.app, "keys_1985", False):
                # 1985 (§6, "the line is rejected"): the line goes, the menu's keys are keys again
                self.say(f"REJECTED: {typed.strip()}: {error}")
                self._menu()
                return
            # rejected: the line stays in the field to be corrected (nothing typed is lost)
            self.say(f"REJECTED: {error}")

    def _read_as_1985(self, typed: str) -> tuple[str, str]:
        """--keys 1985: a step as the 1985 program read it (`CLOSE I 50` is CLOSEI 50), and
        the words the accepted message adds to say so ("" when it is read as typed)."""
        if not getattr(self.app, "keys_1985", False):
            return typed, ""
        from valterm.core.val.checker import read_as_1985

        reading = read_as_1985(typed)
        if reading is None:
            return typed, ""
        return reading, f": {typed.strip()} READ AS {reading.strip()}, AS IN 1985"

    @staticmethod
    def _number(typed: str) -> int:
        text = typed.strip().lstrip(",").strip()
        if not text.isdigit():
            raise EditorError(f"{typed.strip() or 'NOTHING'} IS NOT A STEP NUMBER")
        return int(text)

    def on_unmount(self) -> None:
        """The app ends with the editor open: the journal stays for the next open to recover."""
        if self.editor is not None:
            self.editor.close()

    def close(self) -> None:
        """Dismiss this screen if it is still the one on top: keys typed ahead reach a screen's
        queue before it closes, and a second close must not close the screen below."""
        if self.app.screen is self:
            if self.editor is not None:
                self.editor.close()  # another session may now take its journal over
            self.dismiss(None)
