"""The API reference (docs/api.md, rendered by mkdocstrings) documents every parameter (issue 32, item 9).

For each ``:::`` entry of docs/api.md, the functions the page shows - the function itself, a class's
constructor and public methods, a module's public functions and classes defined in it - each name every
parameter of their signature: in the NumPy-style ``Parameters`` section when the docstring has one
(mkdocstrings renders it as the parameter table, so a parameter left out there is missing from the page),
else in the docstring's text. Dataclasses document their fields as attributes and are skipped.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
ENTRIES = re.findall(r"^::: ([\w.]+)", (ROOT / "docs" / "api.md").read_text(), re.M)
#: a NumPy section header: a name line, then a line of dashes
_SECTION = re.compile(r"^([A-Z][A-Za-z ]*)\n-{3,}\n", re.M)


def _resolve(path: str):
    parts = path.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for p in parts[i:]:
            obj = getattr(obj, p)
        return obj
    raise ImportError(path)


def _shown(obj, name: str) -> list[tuple[str, object]]:
    """(name, callable) of what the reference shows for one entry."""
    if inspect.ismodule(obj):
        names = getattr(obj, "__all__", None) or [n for n in vars(obj) if not n.startswith("_")]
        out = []
        for n in names:
            m = getattr(obj, n, None)
            if (inspect.isfunction(m) or inspect.isclass(m)) and m.__module__ == obj.__name__:
                out += _shown(m, f"{name}.{n}")
        return out
    if inspect.isclass(obj):
        out = [] if dataclasses.is_dataclass(obj) or obj.__init__ is object.__init__ else [(name, obj)]
        for n, m in vars(obj).items():
            if isinstance(m, (staticmethod, classmethod)):
                m = m.__func__
            if not n.startswith("_") and inspect.isfunction(m):
                out.append((f"{name}.{n}", m))
        return out
    return [(name, obj)]


def _parameters_section(doc: str) -> set[str] | None:
    """The names the docstring's Parameters section lists (None: it has none)."""
    sections = list(_SECTION.finditer(doc))
    for k, m in enumerate(sections):
        if m.group(1).strip() in ("Parameters", "Other Parameters"):
            end = sections[k + 1].start() if k + 1 < len(sections) else len(doc)
            names: set[str] = set()
            for line in doc[m.end():end].splitlines():
                if line and not line[0].isspace():      # a parameter line (its description is indented)
                    names.update(p.strip().lstrip("*") for p in line.split(" :")[0].split(","))
            return names
    return None


def _undocumented(f) -> list[str]:
    try:
        sig = inspect.signature(f)
    except (TypeError, ValueError):
        return []
    doc = inspect.getdoc(f) or ""
    if inspect.isclass(f):
        doc += "\n" + (inspect.getdoc(f.__init__) or "")
    want = [p for p in sig.parameters if p not in ("self", "cls")]
    listed = _parameters_section(doc)
    if listed is not None:
        return [p for p in want if p not in listed]
    return [p for p in want if not re.search(rf"(?<![\w.]){re.escape(p)}\b", doc)]


SHOWN = [item for entry in ENTRIES for item in _shown(_resolve(entry), entry)]


def test_the_reference_shows_many_functions():
    assert len(ENTRIES) >= 40 and len(SHOWN) >= 150


@pytest.mark.parametrize("name, f", SHOWN, ids=[n for n, _ in SHOWN])
def test_every_parameter_is_documented(name, f):
    missing = _undocumented(f)
    assert not missing, f"{name}: parameter(s) {', '.join(missing)} not documented in its docstring"
