"""VAL-II: COMMAND.DAT and HELPER.DAT, the statement compiler, the syntax checker and the
two-pass interpreter (Chapter 6, App. C section 3)."""
