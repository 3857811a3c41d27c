"""The VAL-II variables (section 6.7): a dict kept in CHECK.DAT across sessions."""

from __future__ import annotations

from pathlib import Path


class VariableStore(dict[str, float]):
    """NAME -> value.  A plain dict (compiled statements read it directly) with CHECK.DAT hooks;
    a name not in it is ``UndefinedVariable`` (the program's error, not a bare KeyError)."""

    def __missing__(self, name: str) -> float:
        from valterm.core.val.ops import UndefinedVariable

        raise UndefinedVariable(name)

    def load(self, path: str | Path) -> None:
        """Replace the contents with CHECK.DAT (FileFormatError if malformed); missing = empty."""
        from valterm.core.files.variables import read_variables

        path = Path(path)
        values = read_variables(path) if path.exists() else {}
        self.clear()  # in place: compiled programs hold this very dict
        self.update(values)

    def save(self, path: str | Path) -> None:
        from valterm.core.files.variables import write_variables

        write_variables(path, dict(self))
