"""The ``v+`` dialect: the VAL-II of real controllers (Adept V+), decoded and built.

- ``statements``: ``parse_vplus``, a step's text -> a ``Statement`` (arguments kept as text)
- ``expr``: V+ numeric, location and string expressions
- ``builders``: ``VPLUS_BUILDERS``, the statement table, gathered from ``control``, ``calls``,
  ``motions``, ``settings`` and ``signals`` (``compiled``: what they share)

V+ semantics (Adept V+ Language Reference) where the thesis is silent:
- TRUE is -1, FALSE 0; a condition is true when not 0;
- ``FOR`` evaluates its limits each pass, the body is skipped when the start is past the end;
- ``CASE`` runs the first VALUE list holding the value, else ANY, else nothing;
- ``CALL p(a, b)``: a plain variable, location or string argument is passed by reference
  (the caller sees what the subroutine leaves in its parameter), anything else by value;
  parameters and AUTO/LOCAL variables are the subroutine's own, saved and restored around
  the call, so recursion works;
- ``BREAK`` waits for the motion to finish: simulated motions always have;
- ``SPEED n`` stays in force (as in the 1985 dialect), ``ALWAYS`` is accepted;
- ``MOVET loc, hand`` / ``MOVEST``: the motion, then the hand opened (hand not 0) or closed;
- ``REACT``/``REACTI n, prog``: when signal n changes to the wanted state during a motion,
  WAIT, DELAY or SIGNAL step, prog is CALLed after that step (once; ``IGNORE`` disarms);
- locations are X Y Z yaw pitch roll (``core/transform.py``): TRANS, DECOMPOSE, WHERE;
- ``WAIT cond`` lets simulated time pass until cond holds (``first_true``);
- ``EXIT n`` / ``NEXT n`` leave or continue the n-th enclosing FOR, WHILE or DO loop.
"""

from __future__ import annotations

from valterm.core.val.compiler import Grammar
from valterm.core.val.dialect import Dialect
from valterm.core.val.dialects.vplus.builders import VPLUS_BUILDERS
from valterm.core.val.dialects.vplus.settings import vplus_where
from valterm.core.val.dialects.vplus.statements import block_opened, parse_vplus

DIALECT = Dialect(
    Grammar("v+", parse_vplus, block_opened, ends_close="IF, WHILE, FOR or CASE", quoted_comments=True),
    "V+ (ADEPT V+ REFERENCE)", VPLUS_BUILDERS,
    stops_at_error=True,  # the controller stops a program at a step that fails
    missing_program="in the file or the workspace",  # V+ programs live in files (docs/VPLUS.md)
    signals_in_status=True, data_sections=True,
    rules="controller",  # a real PUMA under V+ (SPEC §3a)
    readout=vplus_where)
