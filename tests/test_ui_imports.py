"""The UI's import graph: no circle (imports inside functions count), no screen imports the
app, no screen found by name. Imports under ``if TYPE_CHECKING:`` never run (a screen types
the app it runs in) and are left out, as tests/test_architecture.py's grimp graph does."""

from __future__ import annotations

import ast
from pathlib import Path

import valterm

PACKAGE = Path(valterm.__path__[0])


def _module(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _run_time_nodes(tree: ast.AST) -> list[ast.AST]:
    """Every node but those under ``if TYPE_CHECKING:`` (annotations only: they never run)."""
    nodes: list[ast.AST] = []
    todo = [tree]
    while todo:
        node = todo.pop()
        nodes.append(node)
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
            todo.extend(node.orelse)
            continue
        todo.extend(ast.iter_child_nodes(node))
    return nodes


def _imports(path: Path) -> set[str]:
    found: set[str] = set()
    for node in _run_time_nodes(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("valterm"):
            found.add(node.module)
            found.update(f"{node.module}.{alias.name}" for alias in node.names)
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names if alias.name.startswith("valterm"))
    return found


def _graph() -> dict[str, set[str]]:
    files = {_module(p): p for p in (PACKAGE / "ui").rglob("*.py")}
    return {name: _imports(path) & set(files) for name, path in files.items()}


def test_no_import_circle_in_the_ui() -> None:
    graph = _graph()
    state: dict[str, int] = {}

    def visit(node: str, trail: list[str]) -> None:
        state[node] = 1
        for nxt in sorted(graph[node]):
            assert state.get(nxt) != 1, " -> ".join([*trail, node, nxt])
            if nxt not in state:
                visit(nxt, [*trail, node])
        state[node] = 2

    for name in sorted(graph):
        if name not in state:
            visit(name, [])
    assert "valterm.ui.screens.valmode" in graph["valterm.ui.screens.main_menu"]  # the scan sees imports


def test_screens_do_not_import_the_app_nor_look_screens_up_by_name() -> None:
    for path in (PACKAGE / "ui" / "screens").glob("*.py"):
        if path.name == "demo.py":  # the demo is an App subclass, not a screen of the app
            continue
        text = path.read_text()
        assert "valterm.ui.app" not in _imports(path), path.name
        assert "importlib" not in text, path.name
