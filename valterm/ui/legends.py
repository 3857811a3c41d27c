"""What the user is told about keys, built from the live bindings (issues 35 and 37).

A menu's key letters, HELP's key table, the status line's help hint, VAL-II mode's key lines
and the wrong-key answers all ask here which keys a binding has now (the keymap file's, as
``App.set_keymap`` applied it, else the binding's own) and whether the screen's present state
switches it on (``KeyedScreen.STATES``), so a rebound key is taught as the new key everywhere
and HELP lists only the keys that work where it was asked (posting's help screen does the same).
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import Any

from textual.binding import Binding
from textual.dom import DOMNode

HELP_ID = "screen.help"
HELP = Binding("question_mark,f1", "help", "Help", id=HELP_ID)  # every screen's (KeyedScreen)

_NAMES = {
    "question_mark": "?", "escape": "ESC", "enter": "RETURN", "plus": "+", "minus": "-",
    "equals_sign": "=", "underscore": "_", "pageup": "PGUP", "pagedown": "PGDN", "space": "SPACE",
    "less_than_sign": "<", "greater_than_sign": ">", "tab": "TAB", "backspace": "BACKSPACE",
    "home": "HOME", "end": "END", "left": "LEFT", "right": "RIGHT", "up": "UP", "down": "DOWN",
    "exclamation_mark": "!", "asterisk": "*", "slash": "/", "comma": ",", "full_stop": ".",
}


def keymap_of(node: DOMNode | None) -> dict[str, str]:
    """The rebindings in force (the app keeps what it gave ``set_keymap``)."""
    if node is None:
        return {}
    try:
        app = node.app
    except Exception:  # no app running (a screen built in a test)
        return {}
    keymap: dict[str, str] = getattr(app, "keymap_in_force", {})
    return keymap


def live_keys(node: DOMNode | None, binding: Binding) -> list[str]:
    """The keys ``binding`` has now, in Textual's names."""
    keys = keymap_of(node).get(str(binding.id), binding.key) if binding.id else binding.key
    return [key.strip() for key in keys.split(",") if key.strip()]


def key_label(key: str, others: list[str] | tuple[str, ...] = ()) -> str:
    """A key as the screens write it: ``question_mark`` -> ``?``, ``ctrl+l`` -> ``CTRL-L``, a
    capital alone (no small letter beside it) -> ``SHIFT-X``."""
    key = key.strip()
    if len(key) == 1 and key.isalpha():
        return f"SHIFT-{key}" if key.isupper() and key.lower() not in others else key.upper()
    if key in _NAMES:
        return _NAMES[key]
    *mods, last = key.split("+")
    name = _NAMES.get(last, last.upper())
    return "-".join([*(mod.upper() for mod in mods), name]) if mods else name


def labels(node: DOMNode | None, binding: Binding) -> list[str]:
    """The binding's keys now, as shown (``p,P`` -> ``["P"]``), in order, each once."""
    keys = live_keys(node, binding)
    shown: list[str] = []
    for key in keys:
        label = key_label(key, keys)
        if label not in shown:
            shown.append(label)
    return shown


def shown(node: DOMNode | None, binding: Binding, joint: str = "/") -> str:
    return joint.join(labels(node, binding))


def help_hint(node: DOMNode | None) -> str:
    """``? OR F1: HELP`` as the help key is bound now."""
    return f"{shown(node, HELP, ' OR ')}: HELP"


def short_help_hint(node: DOMNode | None) -> str:
    first = labels(node, HELP)
    return f"{first[0]} HELP" if first else "HELP"


def bindings_of(node: Any) -> Iterator[Binding]:
    """A node's bindings with ids, its own class's first, each id once (Textual's order)."""
    seen: set[str] = set()
    for cls in type(node).__mro__:
        for binding in cls.__dict__.get("BINDINGS", ()):
            if isinstance(binding, Binding) and binding.id and binding.id not in seen:
                seen.add(binding.id)
                yield binding


def action_name(binding: Binding) -> str:
    """The action a binding runs, without its arguments (``joint(1)`` -> ``joint``)."""
    return binding.action.partition("(")[0]


def works_in(node: Any, binding: Binding, state: str) -> bool:
    """True when the screen switches ``binding`` on in ``state`` (its STATES say)."""
    states = getattr(node, "STATES", {}).get(action_name(binding))
    return states is None or state in states


def bound_to(node: Any, action: str, state: str | None = None) -> Binding | None:
    """The screen's binding that runs ``action`` (in ``state``, when given)."""
    for binding in bindings_of(node):
        if action_name(binding) == action and (state is None or works_in(node, binding, state)):
            return binding
    return None


def key_for(node: Any, action: str, default: str, state: str | None = None) -> str:
    """The first key that runs ``action`` now, as shown (``default`` when none does)."""
    binding = bound_to(node, action, state)
    found = labels(node, binding) if binding is not None else []
    return found[0] if found else default


def legend(node: Any, extra: list[tuple[str, str]] | None = None) -> list[tuple[str, str]]:
    """HELP's key table: (keys, what) of every binding that works in the screen's present
    state, with the keys it has now; CTRL-C and CTRL-Q (the app's) last."""
    state = getattr(node, "key_state", "")
    rows = [(shown(node, binding), binding.description.upper()) for binding in bindings_of(node)
            if works_in(node, binding, state) and live_keys(node, binding)]
    return [*rows, *(extra or []), ("CTRL-C", "ABORT A MOTION OR PROGRAM"),
            ("CTRL-Q", "LEAVE (ASKS WHEN WORK IS NOT SAVED)")]


# a key line's field: {binding.id}, {binding.id|C} (C when it is still bound), {binding.id:^} (^L)
_FIELD = re.compile(r"\{([a-z0-9_.]+)(:\^)?(?:\|([^}]+))?\}")


def fill(node: Any, template: str) -> str:
    """A line of keys with each ``{binding.id}`` field as the binding's key now (VAL-II mode's
    key lines: ``{valmode.wipe:^} W_WIPE`` is ``^L W_WIPE`` until the keymap file moves it)."""
    if "{" not in template:
        return template
    by_id = _by_id(node)

    def one(field: re.Match[str]) -> str:
        binding = by_id.get(field.group(1))
        now = labels(node, binding) if binding is not None else []
        if not now:
            return "(NO KEY)"
        label = field.group(3) if field.group(3) in now else now[0]
        return label.replace("CTRL-", "^") if field.group(2) else label

    return _FIELD.sub(one, template)


def _by_id(node: Any) -> dict[str, Binding]:
    return {str(binding.id): binding for binding in (*bindings_of(node), *bindings_of(_app(node)))}


def keys_of(node: Any, *binding_ids: str) -> list[str]:
    """The first key of each binding now, as shown (a question's answers: quit.yes, quit.no)."""
    by_id = _by_id(node)
    found = [labels(node, by_id[binding_id]) if binding_id in by_id else [] for binding_id in binding_ids]
    return [keys[0] for keys in found if keys]


def _app(node: Any) -> Any:
    try:
        return node.app
    except Exception:  # no app running
        return None


# a menu line's key: "K_KEYBOARD", "- 1 - (JOINT 1)", "- W WORLD", "+ / - :"
MENU_KEY = re.compile(r"^(-? ?)(F\d{1,2}|CTRL-[A-Z]|SHIFT-[A-Z]|[A-Z0-9+?])(_| - |\s)")


def live_menu(node: Any, text: str, state: str) -> str:
    """A menu of the thesis with each line's key as it is bound now (``P_PENDANT`` becomes
    ``J_PENDANT`` when the keymap file puts main.pendant on J). A line's key is matched to the
    binding whose own (default) keys hold it and that works in ``state``."""
    lines = []
    for line in text.splitlines():
        match = MENU_KEY.match(line)
        binding = _menu_binding(node, match.group(2), state) if match else None
        if match and binding is not None:
            now = labels(node, binding)
            if now and match.group(2) not in now:
                line = f"{match.group(1)}{now[0]}{line[match.end(2):]}"
        lines.append(line)
    return "\n".join(lines)


def _menu_binding(node: Any, key: str, state: str) -> Binding | None:
    for binding in bindings_of(node):
        keys = [k.strip() for k in binding.key.split(",")]
        if key in (key_label(k, keys) for k in keys) and works_in(node, binding, state):
            return binding
    return None
