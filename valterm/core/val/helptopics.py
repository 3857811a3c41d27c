"""HELPER.DAT as the interpreter sees it: the reader lives in ``valterm.core.files.helpfile``."""

from valterm.core.files.helpfile import (
    HELPER_FILE,
    HelpTopic,
    HelpTopics,
    default_help,
    load_help,
    parse_help_file,
)

__all__ = ["HELPER_FILE", "HelpTopic", "HelpTopics", "default_help", "load_help", "parse_help_file"]
