"""VAL-II: COMMAND.DAT and HELPER.DAT, the statement compiler, the syntax checker and the
two-pass interpreter (Chapter 6, App. C section 3).

- ``commands``: COMMAND.DAT -> ``CommandTable`` (unique-prefix lookup, argument shapes)
- ``helptopics``: HELPER.DAT -> ``HelpTopics`` (``find(prefix)``, ``menu()``)
- ``expr``: expressions and conditions compiled to Python source
- ``parser``: ``parse_statement(text) -> Statement`` or ``ValSyntaxError``
- ``compiler``: pass 1, ``analyse(program) -> Analysis`` (labels, structures, diagnostics)
- ``checker``: ``check_program(program) -> CheckReport``, ``check_statement(text)``
- ``interpreter``: ``Interpreter(sim, load_program, variables)`` with ``execute(name, loops)``,
  ``command(text)``, ``abort()``, ``proceed()``, ``paused``, ``running``, ``status()``
- ``transcript``: events as text lines; ``bench``: ``bench_interpreter()``
"""
