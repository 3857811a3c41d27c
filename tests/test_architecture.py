"""The rules of the layout, checked by tools (issue 11): contracts, no import circles,
small functions, no lookups of modules by name."""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
from pathlib import Path

import grimp
import pytest
from radon.complexity import cc_visit

PACKAGE = Path(__file__).resolve().parent.parent / "valterm"
MAX_FUNCTION_LINES = 80
MAX_COMPLEXITY = 25  # McCabe's cyclomatic complexity, as radon counts it (issue 37)
MAX_MODULE_LINES = 1000


def test_import_contracts_are_kept() -> None:
    """The contracts in pyproject.toml ([tool.importlinter]): the core stays headless."""
    lint = shutil.which("lint-imports", path=str(Path(sys.executable).parent))
    assert lint is not None, "import-linter is a test dependency"
    result = subprocess.run([lint], capture_output=True, text=True, cwd=PACKAGE.parent, timeout=120)
    assert result.returncode == 0, result.stdout[-3000:]


def _cycles(graph: grimp.ImportGraph, modules: set[str]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    found: list[list[str]] = []
    counter = 0
    for root in sorted(modules):
        if root in index:
            continue
        work = [(root, iter(sorted(graph.find_modules_directly_imported_by(root) & modules)))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is None:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        found.append(sorted(component))
            elif child not in index:
                index[child] = low[child] = counter
                counter += 1
                stack.append(child)
                on_stack.add(child)
                work.append((child, iter(sorted(graph.find_modules_directly_imported_by(child) & modules))))
            elif child in on_stack:
                low[node] = min(low[node], index[child])
    return found


def test_no_import_circles_anywhere_in_the_package() -> None:
    """Imports inside functions count: grimp reads every import statement that runs. Imports
    under ``if TYPE_CHECKING:`` never run (annotations only) and are left out."""
    graph = grimp.build_graph("valterm", include_external_packages=False, exclude_type_checking_imports=True)
    modules = {m for m in graph.modules if m.startswith("valterm")}
    assert _cycles(graph, modules) == []


def _functions(tree: ast.AST) -> list[ast.FunctionDef | ast.AsyncFunctionDef]:
    return [node for node in ast.walk(tree) if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))]


def test_no_function_over_80_lines() -> None:
    long = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for function in _functions(ast.parse(path.read_text(encoding="utf-8"))):
            length = (function.end_lineno or function.lineno) - function.lineno + 1
            if length > MAX_FUNCTION_LINES:
                long.append(f"{path.relative_to(PACKAGE.parent)}:{function.lineno} {function.name} ({length} lines)")
    assert long == []


def test_no_function_over_complexity_25() -> None:
    """A function with more than 25 paths through it is a table or several functions (issue 37:
    the V+ statement decoder was 52)."""
    tangled = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for block in cc_visit(path.read_text(encoding="utf-8")):  # functions and methods (and classes: "C")
            if block.letter in "FM" and block.complexity > MAX_COMPLEXITY:
                tangled.append(f"{path.relative_to(PACKAGE.parent)}:{block.lineno} {block.name} "
                               f"(complexity {block.complexity})")
    assert tangled == []


def test_no_module_over_1000_lines() -> None:
    long = [f"{path.relative_to(PACKAGE.parent)} ({count} lines)" for path in sorted(PACKAGE.rglob("*.py"))
            if (count := len(path.read_text(encoding="utf-8").splitlines())) > MAX_MODULE_LINES]
    assert long == []


def test_no_modules_looked_up_by_name() -> None:
    """Screens and commands are imported directly: an import error is a bug, not a message."""
    offenders = [str(p.relative_to(PACKAGE.parent)) for p in sorted(PACKAGE.rglob("*.py"))
                 if "importlib.import_module" in p.read_text(encoding="utf-8")
                 or "__import__(" in p.read_text(encoding="utf-8")]
    assert offenders == []


@pytest.mark.parametrize("forbidden", ["exec(", "eval("])
def test_no_code_generation_in_the_core(forbidden: str) -> None:
    offenders = []
    for path in sorted((PACKAGE / "core").rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == forbidden[:-1]:
                offenders.append(f"{path.name}:{node.lineno}")
    assert offenders == []
