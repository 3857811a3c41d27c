"""The screens: start, MAIN, KEYBOARD, PENDANT, MANIPULATION, EDITOR, VAL-II and HELP.

Each is imported directly where it is opened; no screen imports the app (``valterm.ui.app``):
they reach the app's shared state through ``self.app``.
"""
