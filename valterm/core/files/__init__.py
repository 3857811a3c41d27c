"""Readers and writers of the workspace files (SPEC §5).

Every reader raises :class:`FileFormatError` (``NAME.SET:12: reason``) for any malformed
input and nothing else; every writer is atomic.
"""

from valterm.core.files.atomic import write_text_atomic
from valterm.core.files.datfiler import add_program_name, format_datfiler, parse_datfiler, read_datfiler, write_datfiler
from valterm.core.files.errors import FileFormatError
from valterm.core.files.locations import (
    check_location_name,
    format_locations,
    parse_locations,
    read_locations,
    write_locations,
)
from valterm.core.files.programs import Program, ProgramLine, format_program, parse_program, read_program, write_program
from valterm.core.files.setup import format_setup, parse_setup, read_setup, write_setup
from valterm.core.files.variables import format_variables, parse_variables, read_variables, write_variables

__all__ = [
    "FileFormatError",
    "Program",
    "ProgramLine",
    "add_program_name",
    "check_location_name",
    "format_datfiler",
    "format_locations",
    "format_program",
    "format_setup",
    "format_variables",
    "parse_datfiler",
    "parse_locations",
    "parse_program",
    "parse_setup",
    "parse_variables",
    "read_datfiler",
    "read_locations",
    "read_program",
    "read_setup",
    "read_variables",
    "write_datfiler",
    "write_locations",
    "write_program",
    "write_setup",
    "write_text_atomic",
    "write_variables",
]
