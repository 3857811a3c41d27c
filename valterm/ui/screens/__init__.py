"""The screens: start, MAIN, KEYBOARD, PENDANT and MANIPULATION menus (this package's own),
and the EDITOR, VAL-II and HELP screens that the main menu opens by name.
"""

from __future__ import annotations

import importlib

from textual.screen import Screen

# The main menu's keys that open screens written elsewhere, by import path.
EXTERNAL_SCREENS = {
    "editor": ("valterm.ui.screens.editor", "EditorScreen"),
    "valmode": ("valterm.ui.screens.valmode", "ValModeScreen"),
    "help": ("valterm.ui.screens.help", "HelpScreen"),
}


def external_screen(kind: str) -> Screen | None:
    """A new EDITOR / VAL-II / HELP screen, or None when that screen is not there yet."""
    module_name, class_name = EXTERNAL_SCREENS[kind]
    try:
        module = importlib.import_module(module_name)
        screen_class = getattr(module, class_name)
    except (ImportError, AttributeError):
        return None
    return screen_class()
