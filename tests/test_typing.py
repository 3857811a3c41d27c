"""The whole package stays clean: `mypy --strict` and `ruff check` (issues 11 and 27).

Both tools read their settings from pyproject.toml (the core is strict there). Every module of
the package is listed (found, not hand-kept). The tools come from the `test` extra, in the running interpreter's
bin folder; a missing tool fails the test rather than skipping it.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

# The whole package is held to `mypy --strict` and ruff (the core since issue 11, the UI and
# the rest since issue 27): every module of it.
CLEAN_FILES = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "valterm").rglob("*.py"))


def _tool(name: str) -> str:
    """The tool installed beside the running interpreter (the `test` extra)."""
    found = shutil.which(name, path=str(Path(sys.executable).parent))
    if found is None:
        pytest.fail(f"{name} is not installed beside {sys.executable}: pip install -e '.[test]'")
    return found


def _run(command: list[str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=300)


def test_listed_files_exist() -> None:
    missing = [name for name in CLEAN_FILES if not (ROOT / name).is_file()]
    assert not missing, f"listed as clean but not there: {missing}"


@pytest.mark.slow  # CI runs it (pytest -m slow); the default run stays under 5 minutes
def test_clean_files_pass_mypy_strict(tmp_path: Path) -> None:
    result = _run([_tool("mypy"), "--cache-dir", str(tmp_path / "mypy"), *CLEAN_FILES])
    assert result.returncode == 0, result.stdout + result.stderr
    assert "Success: no issues found" in result.stdout


def test_the_core_is_strict_in_the_config(tmp_path: Path) -> None:
    """The strictness comes from pyproject.toml: an unannotated core module fails there."""
    package = tmp_path / "valterm" / "core"
    package.mkdir(parents=True)
    for folder in (package.parent, package):
        (folder / "__init__.py").write_text("", encoding="utf-8")
    (package / "probe.py").write_text("def untyped(x):\n    return x\n", encoding="utf-8")
    result = subprocess.run(
        [_tool("mypy"), "--config-file", str(ROOT / "pyproject.toml"), "--cache-dir", str(tmp_path / "cache"),
         "valterm/core/probe.py"],
        cwd=tmp_path, capture_output=True, text=True, timeout=300,
    )
    assert result.returncode == 1, result.stdout + result.stderr
    assert "[no-untyped-def]" in result.stdout


def test_the_whole_package_passes_ruff() -> None:
    """ruff's rules (pyproject.toml) hold everywhere: the core, the app, the CLI, the benches."""
    result = _run([_tool("ruff"), "check", "--no-cache", "valterm"])
    assert result.returncode == 0, result.stdout + result.stderr
