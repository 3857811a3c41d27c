"""Subcommands of the ``valterm`` command line, one module each.

Each module defines ``register(subparsers)`` which adds its parser and sets
``func=<callable(args) -> int>`` as the default. ``valterm.cli`` lists them.
"""
