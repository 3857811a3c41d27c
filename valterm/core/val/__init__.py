"""VAL-II: the statement compiler, the syntax checker and the two-pass interpreter
(Chapter 6, App. C section 3).

- ``commands`` / ``helptopics``: COMMAND.DAT and HELPER.DAT as read by
  ``valterm.core.files.commandfile`` / ``helpfile`` (``CommandTable``, ``HelpTopics``)
- ``expr``: expressions and conditions parsed into typed nodes, run as closures
- ``parser``: ``parse_statement(text) -> Statement`` or ``ValSyntaxError``
- ``compiler``: pass 1, ``analyse(program) -> Analysis`` (labels, structures, diagnostics)
- ``checker``: ``check_program(program) -> CheckReport``, ``check_statement(text)``
- ``ops``: the typed ops of pass 2 (``Assign``, ``Branch``, ``Jump``, ``Action``, ``Call``,
  ``Return``, ``Stop``, ``PauseOp``) and ``ProgramError`` (program and step)
- ``builders``: ``Build`` (what a builder knows) and the builders every dialect shares
  (the block structure and CALL, ``STRUCTURE``)
- ``protocol``: ``Simulator``, what the interpreter needs from the simulator
- ``interpreter``: ``Interpreter(sim, load_program, variables)`` with ``execute(name, loops)``,
  ``command(text)``, ``abort()``, ``proceed()``, ``paused``, ``running``, ``status()``,
  ``hook`` (called before each step), ``builders`` and ``monitor`` (the dialect's tables)
- ``transcript``: events as text lines
- ``typeout``: TYPE's output list (quoted text, values, /F /I /E /H /X /C formats)
- ``machine``: the controller's state (signals, strings, precision points, timers, TOOL)
- ``dialect``: ``Dialect``, what a dialect is to the shared core (its ``Grammar`` for pass 1,
  its statement table, how its controller differs)
- ``dialects``: the registry (``NAMES``, ``dialect(name)``, ``check_dialect``) and one
  package per dialect with its statement table: ``val1985`` (the thesis's COMMAND.DAT,
  ``BUILDERS``), ``vplus`` (issue 14, docs/VPLUS.md: ``parse_vplus``, ``VPLUS_BUILDERS``,
  V+ expressions); docs/ARCHITECTURE.md says how to add one
"""
