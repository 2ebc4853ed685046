"""The house keeps its plan: layers that only look down, no import cycles, small folders and modules.

The import graph is built from the source with ``ast`` (``.py``) and, for the compiled core's Python-level
imports, from the ``.pyx`` lines that ``import``/``from ... import`` (Cython's ``cimport`` is compile
time only and stays inside ``robkin.compiled``). Every import counts: at module level, inside functions,
and under ``if TYPE_CHECKING:`` (an import a type checker follows is a dependency all the same). The
layers are the ones CONTRIBUTING.md documents; the two lists below must say the same.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = SRC / "robkin"

#: Bottom to top. A module belongs to the first layer whose prefix it has (a prefix is a module or a
#: package); within a layer, packages may use each other but form no cycle. (CONTRIBUTING.md, "Layers".)
LAYERS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("leaves", ("robkin.errors", "robkin.messages", "robkin.names", "robkin.lazy_exports", "robkin.se3",
                "robkin.lines", "robkin.samples", "robkin.version", "robkin.examples")),
    ("compiled", ("robkin.compiled",)),
    ("core", ("robkin.checks", "robkin.threads", "robkin.frame_stacks")),
    ("hub", ("robkin.robot", "robkin.joints", "robkin.bodies", "robkin.body_parts", "robkin.link_geometry",
             "robkin.mass_properties", "robkin.capabilities")),
    ("representations", ("robkin.representations",)),
    ("io", ("robkin.io",)),
    ("capabilities", ("robkin.kinematics", "robkin.equivalence", "robkin.dynamics", "robkin.calibration",
                      "robkin.synthesis", "robkin.simulation", "robkin.collision", "robkin.lint",
                      "robkin.workspace", "robkin.self_collision")),
    ("viz", ("robkin.viz",)),
    ("front", ("robkin.commands", "robkin.cli", "robkin")),
)

#: The declared facades: the only modules that may import from a higher layer (each says "facade" in its
#: docstring; at most one per layer). Their upward edges are left out of the cycle check: a facade is the
#: documented way up, imported lazily by design.
FACADES = {
    "robkin.capabilities": "hub",
    "robkin.representations.presentation": "representations",
}

#: Largest source folder (modules: .py and .pyx files) and largest module (lines).
MAX_MODULES_PER_FOLDER = 20
MAX_MODULE_LINES = 500

_PYX_IMPORT = re.compile(r"^\s*(?:from\s+([\w.]+)\s+import\s+(.+)|import\s+([\w., ]+))$")


def _module_name(path: Path) -> tuple[str, bool]:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    is_package = parts[-1] == "__init__"
    if is_package:
        parts = parts[:-1]
    return ".".join(parts), is_package


def _modules() -> dict[str, tuple[Path, bool]]:
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")) + sorted(PACKAGE.rglob("*.pyx")):
        name, is_package = _module_name(path)
        found.setdefault(name, (path, is_package))
    return found


MODULES = _modules()


def _known(target: str) -> str | None:
    """The module an imported dotted name lives in (``robkin.io.urdf.parse_urdf`` -> ``robkin.io.urdf``)."""
    while target and target not in MODULES:
        if "." not in target:
            return None
        target = target.rsplit(".", 1)[0]
    return target or None


def _absolute(module: str, is_package: bool, level: int, name: str | None) -> str:
    base = module.split(".")
    if not is_package:
        base = base[:-1]
    if level > 1:
        base = base[: len(base) - (level - 1)]
    return ".".join(base + ([name] if name else []))


def _imports_py(module: str, source: str, is_package: bool) -> set[str]:
    out = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            prefix = _absolute(module, is_package, node.level, node.module) if node.level else (node.module or "")
            targets = [f"{prefix}.{a.name}" for a in node.names]
        else:
            continue
        out.update(t for t in map(_known, targets) if t is not None and t != module)
    return out


def _imports_pyx(module: str, path: Path) -> set[str]:
    out = set()
    for line in path.read_text().splitlines():
        m = _PYX_IMPORT.match(line.split("#")[0].rstrip())
        if not m or "cimport" in line:
            continue
        if m.group(1):
            targets = [f"{m.group(1)}.{n.strip().split(' as ')[0]}" for n in m.group(2).strip("()").split(",")]
        else:
            targets = [n.strip().split(" as ")[0] for n in m.group(3).split(",")]
        out.update(t for t in map(_known, targets) if t is not None and t != module)
    return out


def import_graph() -> dict[str, set[str]]:
    """Module -> the robkin modules it imports (anywhere in its source)."""
    graph = {}
    for name, (path, is_package) in MODULES.items():
        graph[name] = (_imports_pyx(name, path) if path.suffix == ".pyx"
                       else _imports_py(name, path.read_text(), is_package))
    return graph


def layer_of(module: str) -> int:
    for k, (_, prefixes) in enumerate(LAYERS):
        if any(module == p or module.startswith(p + ".") for p in prefixes if p != "robkin"):
            return k
    if module == "robkin":
        return len(LAYERS) - 1
    raise AssertionError(f"{module}: in no layer; add it to LAYERS here and in CONTRIBUTING.md")


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []
    counter = 0
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            v, it = work[-1]
            advanced = False
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                    advanced = True
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
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
    return found


GRAPH = import_graph()


def test_every_module_has_a_layer():
    for module in MODULES:
        layer_of(module)


def test_layers_only_look_down():
    upward = [f"{a} ({LAYERS[layer_of(a)][0]}) imports {b} ({LAYERS[layer_of(b)][0]})"
              for a, targets in sorted(GRAPH.items()) if a not in FACADES
              for b in sorted(targets) if layer_of(b) > layer_of(a)]
    assert upward == []


def test_no_import_cycles():
    # a facade's upward edges are its purpose; every other edge counts
    graph = {a: {b for b in targets if not (a in FACADES and layer_of(b) > layer_of(a))}
             for a, targets in GRAPH.items()}
    assert _cycles(graph) == []


def test_the_cycle_finder_finds_cycles():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_facades_are_declared_in_their_docstrings_one_per_layer():
    layers = [layer_of(f) for f in FACADES]
    assert len(layers) == len(set(layers))
    for facade, layer in FACADES.items():
        path, _ = MODULES[facade]
        doc = ast.get_docstring(ast.parse(path.read_text())) or ""
        assert "facade" in doc.lower(), facade
        assert LAYERS[layer_of(facade)][0] == layer


def test_no_class_is_patched_from_another_module():
    """No ``setattr(Imported, ...)`` and no ``Imported.attr = ...`` at any level of a module."""
    patched = []
    for name, (path, _) in MODULES.items():
        if path.suffix != ".py":
            continue
        tree = ast.parse(path.read_text())
        imported = {a.asname or a.name.split(".")[0] for node in ast.walk(tree)
                    if isinstance(node, (ast.Import, ast.ImportFrom)) for a in node.names}
        for node in ast.walk(tree):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "setattr"
                    and node.args and isinstance(node.args[0], ast.Name) and node.args[0].id in imported):
                patched.append(f"{name}:{node.lineno}")
            if isinstance(node, (ast.Assign, ast.AugAssign)):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                for t in targets:
                    if (isinstance(t, ast.Attribute) and isinstance(t.value, ast.Name) and t.value.id in imported
                            and t.value.id[:1].isupper()):
                        patched.append(f"{name}:{node.lineno}")
    assert patched == []


def test_folders_and_modules_stay_small():
    folders: dict[Path, int] = {}
    for path, _ in MODULES.values():
        folders[path.parent] = folders.get(path.parent, 0) + 1
    crowded = {str(f.relative_to(SRC)): n for f, n in folders.items() if n > MAX_MODULES_PER_FOLDER}
    assert crowded == {}
    long = {str(p.relative_to(SRC)): n for p, _ in MODULES.values()
            if (n := len(p.read_text().splitlines())) > MAX_MODULE_LINES}
    assert long == {}


@pytest.mark.parametrize("source, expected", [
    ("from .io.urdf import parse_urdf", {"robkin.io.urdf"}),
    ("from .io.urdf.parser import parse_urdf as p", {"robkin.io.urdf.parser"}),
    ("from . import se3", {"robkin.se3"}),
    ("def f():\n    import robkin.viz.gui\n", {"robkin.viz.gui"}),
    ("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .robot import Robot\n", {"robkin.robot"}),
])
def test_the_graph_reads_every_kind_of_import(source, expected):
    assert _imports_py("robkin.checks", source, False) == expected
