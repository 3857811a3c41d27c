"""The keyboard model of every screen, written down once (docs/KEYBOARD.md says the same).

1. A screen is either ASKING (a prompt is open: a typed line or a single-key question) or
   at its MENU. While asking, every key belongs to the prompt: printable keys are text,
   RETURN ends the line, and nothing reaches the menu. At the menu, keys are menu keys.
2. ESC cancels the innermost prompt and returns to that screen's menu. At a mode's menu
   (no prompt open) ESC returns to the MAIN MENU, like R. Nothing typed into the cell is
   lost by ESC: an unsaved set-up stays in the session and the status line says NOT SAVED.
3. ``?`` and F1 open HELP for the current screen (at a menu; in a prompt ``?`` is text).
4. A key that means nothing where it is pressed gets a one-line answer naming ``?``; at the
   KEYBOARD and PENDANT menus a letter that is no menu key opens V's command line with it typed.
5. CTRL-C aborts a running motion or program; CTRL-Q leaves the program, asking first when
   there is unsaved work.
"""

from __future__ import annotations

from textual import events

HELP_KEYS = frozenset({"question_mark", "f1"})
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


def is_help(event: events.Key) -> bool:
    return event.key in HELP_KEYS


def is_silent(event: events.Key) -> bool:
    """Keys that get no answer at a menu (modifiers alone, focus keys, pasted whitespace)."""
    return event.key in _SILENT or (event.character is not None and event.character.isspace()
                                    and event.key not in ("enter", "space"))


def unknown_key(event: events.Key, hint: str = "") -> str:
    """The one-line answer to a key that means nothing at this menu (with the screen's hint)."""
    return f"'{key_name(event)}' IS NOT A KEY OF THIS MENU; {hint + '; ' if hint else ''}{HELP_HINT}"


def wrong_answer(event: events.Key, keys: str) -> str:
    """The one-line answer to a key that is not one of a question's answers."""
    choices = ", ".join(k for k in keys if k.isprintable() and k.strip())
    return f"'{key_name(event)}' IS NOT AN ANSWER: PRESS {choices} (ESC CANCELS)"


def legend(node) -> list[tuple[str, str]]:  # type: ignore[no-untyped-def]
    """(keys, what they do) of a screen's bindings, for HELP's key legend."""
    rows: list[tuple[str, str]] = []
    for binding in getattr(node, "BINDINGS", []):
        key, description = (binding.key, binding.description) if hasattr(binding, "key") else (binding[0], binding[2])
        shown = sorted({k.strip().upper().replace("QUESTION_MARK", "?") for k in key.split(",")})
        rows.append(("/".join(shown), description.upper()))
    rows += [("ESC", "CANCEL THE PROMPT; AT A MENU: BACK TO THE MAIN MENU"), ("? F1", "THIS HELP"),
             ("CTRL-C", "ABORT A MOTION OR PROGRAM"), ("CTRL-Q", "LEAVE (ASKS WHEN WORK IS NOT SAVED)")]
    return rows


def keys_of(screen, binding_ids: tuple[str, ...]) -> str:  # type: ignore[no-untyped-def]
    """The keys bound now (the user's keymap applied) to these bindings of ``screen``, as a
    legend says them: ``SHIFT+UP/SHIFT+DOWN``; "" when none is bound."""
    found: dict[str, list[str]] = {binding_id: [] for binding_id in binding_ids}
    for key, active in screen.active_bindings.items():
        if active.binding.id in found:
            found[active.binding.id].append(key.upper().replace("QUESTION_MARK", "?"))
    return "/".join(key for binding_id in binding_ids for key in found[binding_id])
