"""COMMAND.DAT as the interpreter sees it: the reader lives in ``valterm.core.files.commandfile``."""

from valterm.core.files.commandfile import (
    COMMAND_FILE,
    SLOT_KINDS,
    USES,
    AmbiguousCommand,
    CommandSpec,
    CommandTable,
    Item,
    Literal,
    Slot,
    UnknownCommand,
    default_commands,
    load_commands,
    parse_command_file,
)

__all__ = [
    "COMMAND_FILE", "SLOT_KINDS", "USES", "AmbiguousCommand", "CommandSpec", "CommandTable", "Item",
    "Literal", "Slot", "UnknownCommand", "default_commands", "load_commands", "parse_command_file",
]
