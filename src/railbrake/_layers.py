"""The package's layers, one way down, and its import graph read from the source.

The data flow of the developers' guide (files -> one resolved configuration -> C structs and runs
-> results -> plots and reports) as a table: each module of railbrake belongs to the first layer
whose prefixes name it, and imports (at module level or inside a function alike) only from its own
layer or those below. tests/unit/architecture checks it and that the graph has no cycle;
docs/architecture.md renders the table. Reads source text only (ast): imports nothing of railbrake.
"""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = "railbrake"

# (layer, what it holds, module prefixes), lowest first. A prefix names a module and its submodules.
LAYERS = (
    ("foundations", "units, errors, argument checks, JSON, whole-or-absent output files, the layer table",
     ("railbrake.units", "railbrake.errors", "railbrake._args", "railbrake.jsonio", "railbrake.atomic",
      "railbrake._changes", "railbrake._layers", "railbrake._version")),
    ("core binding", "ctypes mirror of the C core's structs and functions (every law is in core/)",
     ("railbrake._core",)),
    ("data and schemas", "data files read and validated: trains, scenarios, adhesion conditions, valves, "
     "pneumatic elements, deceleration profiles, wheel-rail contact",
     ("railbrake.config", "railbrake.vehicle", "railbrake.scenario", "railbrake.contact", "railbrake.adhesion",
      "railbrake.pneumatics", "railbrake.valves", "railbrake.train_template", "railbrake.profiles",
      "railbrake.pad_fade")),
    ("resolution", "one resolved, validated configuration; sizing of the brake steps on a train",
     ("railbrake.resolve", "railbrake.sizing")),
    ("C structs", "the C core's structs of a resolved configuration, its KPIs back as a dict",
     ("railbrake.simulation.parameters", "railbrake.simulation.traction")),
    ("results, plots and reports", "the Result type, its KPIs, records, files and readers; figures of results",
     ("railbrake.results", "railbrake.plots")),
    ("runs", "whole runs in the core (real-time and detailed models) into a Result",
     ("railbrake.simulation",)),
    ("studies and systems", "campaigns, ETCS braking curves, brake calculation reports, validation cases, HIL, "
     "sequences, FMU export, valve reduction on the detailed model",
     ("railbrake.campaign", "railbrake.etcs", "railbrake.brakecalc", "railbrake.validation", "railbrake.hil",
      "railbrake.sequence", "railbrake.fmu", "railbrake.valves.reduce")),
    ("command line", "the railbrake command and the package's face",
     ("railbrake.cli", "railbrake._entry", "railbrake.__main__", "railbrake")),
)


def layer_of(module: str) -> int:
    """Index in LAYERS of a module (the longest matching prefix wins)."""
    best, length = None, -1
    for index, (_, _, prefixes) in enumerate(LAYERS):
        for prefix in prefixes:
            if (module == prefix or module.startswith(prefix + ".")) and len(prefix) > length:
                best, length = index, len(prefix)
    if best is None:
        raise KeyError(f"{module}: in no layer of railbrake._layers.LAYERS")
    return best


def source_root() -> Path:
    return Path(__file__).resolve().parent


def modules(root: Path | None = None) -> dict[str, Path]:
    """Every module of the package: dotted name -> file."""
    root = source_root() if root is None else root
    found = {}
    for path in sorted(root.rglob("*.py")):
        parts = (PACKAGE,) + path.relative_to(root).with_suffix("").parts
        found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return found


def _target(name: str, known: dict) -> str | None:
    """The module an imported dotted name lands in: itself, or the closest enclosing module."""
    while name and name not in known:
        name = name.rpartition(".")[0]
    return name or None


def imports(module: str, path: Path, known: dict) -> set[str]:
    """The railbrake modules `module` imports anywhere in its file (relative imports resolved);
    `from package import name` counts as the submodule when name is one, else as the package."""
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            names = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base for alias in node.names]
        else:
            continue
        found |= {t for t in (_target(n, known) for n in names if n.split(".")[0] == PACKAGE) if t and t != module}
    return found


def graph(root: Path | None = None) -> dict[str, set[str]]:
    """module -> the railbrake modules it imports."""
    known = modules(root)
    return {name: imports(name, path, known) for name, path in known.items()}


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each sorted."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return found


def upward(edges: dict[str, set[str]]) -> list[tuple[str, str]]:
    """(importer, imported) pairs where the imported module sits in a higher layer."""
    return sorted((a, b) for a, targets in edges.items() for b in targets if layer_of(b) > layer_of(a))


def table(root: Path | None = None) -> list[tuple[str, str, list[str]]]:
    """(layer, what it holds, the prefixes of it that name modules) from the bottom up, for the docs."""
    names = modules(root)
    return [(layer, what, [p for p in prefixes if any(n == p or n.startswith(p + ".") for n in names)])
            for layer, what, prefixes in LAYERS]
