"""The keyboard model of every screen, written down once (docs/KEYBOARD.md says the same).

1. A screen is either ASKING (a prompt is open: a typed line or a single-key question) or
   at its MENU. While asking, every key belongs to the prompt: printable keys are text,
   RETURN ends the line, and nothing reaches the menu. At the menu, keys are menu keys.
2. ESC cancels the innermost prompt and returns to that screen's menu. At a mode's menu
   (no prompt open) ESC returns to the MAIN MENU, like R. Nothing typed into the cell is
   lost by ESC: an unsaved set-up stays in the session and the status line says NOT SAVED.
3. ``?`` and F1 open HELP for the current screen (at a menu; in a prompt ``?`` is text): one
   binding, ``screen.help`` (ui/legends.py), that a keymap file moves like any other; what
   the screens say about keys is built from the live bindings there.
4. A key that means nothing where it is pressed gets a one-line answer naming ``?``; at the
   KEYBOARD and PENDANT menus a letter that is no menu key opens V's command line with it typed.
5. CTRL-C aborts a running motion or program; CTRL-Q leaves the program, asking first when
   there is unsaved work.
"""

from __future__ import annotations

from textual import events

CANCEL_KEY = "escape"
HELP_HINT = "? OR F1: HELP"
# keys that never get the "not a key" answer: modifiers and focus moves Textual handles
_SILENT = frozenset({"shift", "ctrl", "alt", "meta", "tab", "shift+tab"})


def key_name(event: events.Key) -> str:
    """The key as the user knows it: the character typed, or the key's name in capitals."""
    char = event.character or ""
    if char and char.isprintable() and char.strip():
        return char.upper()
    return event.key.upper().replace("_", " ")


def is_silent(event: events.Key) -> bool:
    """Keys that get no answer at a menu (modifiers alone, focus keys, pasted whitespace)."""
    return event.key in _SILENT or (event.character is not None and event.character.isspace()
                                    and event.key not in ("enter", "space"))


def unknown_key(event: events.Key, hint: str = "", help_hint: str = HELP_HINT) -> str:
    """The one-line answer to a key that means nothing at this menu (with the screen's hint
    and the help key as it is bound now: ``legends.help_hint``)."""
    return f"'{key_name(event)}' IS NOT A KEY OF THIS MENU; {hint + '; ' if hint else ''}{help_hint}"


def wrong_answer(event: events.Key, keys: str | list[str], cancel: str = "ESC") -> str:
    """The one-line answer to a key that is not one of a question's answers (``cancel``: the
    key that cancels the question as it is bound now, ``legends.key_for``)."""
    choices = ", ".join(k for k in keys if k.isprintable() and k.strip())
    return f"'{key_name(event)}' IS NOT AN ANSWER: PRESS {choices} ({cancel} CANCELS)"
