"""The 1985 dialect: the thesis's VAL-II, its statements read from COMMAND.DAT."""
