"""The package's layers (issue 42), read from the source with ast (railbrake._layers): no import
circle among the modules (module-level and function-level imports alike), each module imports
only from its own layer or the ones below, and every package's __init__.py is a face."""

from __future__ import annotations

import ast

import pytest

from railbrake import _layers

GRAPH = _layers.graph()


def test_every_module_is_in_a_layer():
    for module in GRAPH:
        _layers.layer_of(module)   # raises, naming the module, for one the table forgot


def test_the_graph_sees_function_level_and_relative_imports(tmp_path):
    package = tmp_path / "railbrake"
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "low.py").write_text("X = 1\n")
    (package / "sub" / "__init__.py").write_text("from . import high\n")
    (package / "sub" / "high.py").write_text("def f():\n    from ..low import X\n    import railbrake.sub\n")
    edges = _layers.graph(package)
    assert edges["railbrake.sub"] == {"railbrake.sub.high"}
    assert edges["railbrake.sub.high"] == {"railbrake.low", "railbrake.sub"}
    assert _layers.cycles(edges) == [["railbrake.sub", "railbrake.sub.high"]]


def test_an_upward_import_is_seen():
    edges = {"railbrake.units": {"railbrake.cli.root"}, "railbrake.simulation.runs": {"railbrake.results.scripting"}}
    assert _layers.upward(edges) == [("railbrake.units", "railbrake.cli.root")]


def test_no_import_circle():
    found = _layers.cycles(GRAPH)
    assert not found, "\n".join(
        " <-> ".join(c) + ": " + "; ".join(f"{a} imports {sorted(set(GRAPH[a]) & set(c))}" for a in c)
        for c in found)


def test_no_module_imports_from_a_layer_above_its_own():
    names = [layer for layer, _, _ in _layers.LAYERS]
    up = [f"{a} ({names[_layers.layer_of(a)]}) imports {b} ({names[_layers.layer_of(b)]})"
          for a, b in _layers.upward(GRAPH)]
    assert not up, "\n".join(up)


# ------------------------------------------------------------------ packages' faces

FACE_LINES = 60
INITS = sorted(p for p in _layers.modules().values() if p.name == "__init__.py")


def _body(path) -> list:
    tree = ast.parse(path.read_text())
    body = tree.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
            and isinstance(body[0].value.value, str):
        body = body[1:]   # the docstring
    return body


@pytest.mark.parametrize("path", INITS, ids=lambda p: str(p.relative_to(_layers.source_root())))
def test_init_is_a_face(path):
    body = _body(path)
    tree = ast.parse(path.read_text())
    docstring_end = tree.body[0].end_lineno if ast.get_docstring(tree, clean=False) is not None else 0
    used = len(path.read_text().splitlines()) - docstring_end   # blank lines and comments count too
    assert used <= FACE_LINES, f"{path}: {used} lines after the docstring (at most {FACE_LINES})"
    for node in ast.walk(ast.Module(body=body, type_ignores=[])):
        if isinstance(node, ast.ClassDef):
            pytest.fail(f"{path}, line {node.lineno}: class {node.name}: a face defines no class")
        # a lazy import (PEP 562: a module's __getattr__ and the __dir__ that lists its names) is no logic
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name not in ("__getattr__", "__dir__"):
            pytest.fail(f"{path}, line {node.lineno}: def {node.name}: logic belongs in a module named for it")


def test_the_face_check_sees_a_function(tmp_path):
    face = tmp_path / "__init__.py"
    face.write_text('"""Doc."""\nfrom x import y\n\ndef helper():\n    return 1\n')
    assert [n.name for n in _body(face) if isinstance(n, ast.FunctionDef)] == ["helper"]
