"""The two sets of rules for the robot's joint state (SPEC §3a, docs/MOTION.md).

- ``1985`` (the thesis, §6.1.2: "the angles displayed for a particular configuration are always
  the same regardless of the paths followed"): after every pose each joint is the 360-degree
  equivalent inside its stops, the one in (-180, 180] where two are; a location's stored
  configuration must agree with the user's indicators.
- ``controller`` (a real PUMA under V+): joints wind, and WHERE shows the wound angle; a motion to
  a transformation keeps the arm's configuration unless one was asked for.

The dialect picks the default (1985 -> ``1985``, v+ -> ``controller``); ``--rules`` overrides it.
"""

from __future__ import annotations

from valterm.core.errors import RefusedValue

RULES_1985 = "1985"
CONTROLLER = "controller"
RULES: tuple[str, ...] = (RULES_1985, CONTROLLER)


def check_rules(name: str) -> str:
    """The rules' name as the core spells it, or RefusedValue."""
    word = name.strip().lower()
    if word not in RULES:
        raise RefusedValue(f"{name!r} is not a set of rules: use 1985 or controller")
    return word


def rules_of_dialect(dialect: str) -> str:
    """The default rules of a dialect (its ``Dialect.rules``): the thesis's for 1985, the
    controller's for v+."""
    from valterm.core.val.dialects import dialect as named  # loads that dialect only when asked

    return named(dialect).rules
