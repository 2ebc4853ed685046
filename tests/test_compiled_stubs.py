"""Every compiled extension module (each ``.pyx`` under ``src/robkin/compiled/``) has a type stub beside it
(``<name>.pyi``), and the stub says what the module has:

- every function, class and method the stub declares exists in the module with the same parameters
  (names, kinds, defaults), as ``inspect.signature`` reads the compiled functions (Cython 3
  cyfunctions carry their signatures); every variable it declares (``NAME: type``) exists;
- every public function and class defined in the module (a name not starting with ``_``), and every
  public method of such a class, is declared in the stub.

A constructor (``def __init__`` / ``def __cinit__`` of a ``cdef class``) is a slot of the extension type,
without a signature Python can read: the stub's ``__init__`` is compared with the declaration in the
``.pyx`` instead. The stubs are what mypy sees of the compiled core (``tests/test_typing.py``), so a stub
that drifts from its module hides errors there.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import re
from pathlib import Path
from typing import Any

import pytest

import robkin.compiled

COMPILED = Path(robkin.compiled.__file__).resolve().parent
SOURCES = sorted(COMPILED.rglob("*.pyx"))
KIND = inspect.Parameter
NO_DEFAULT = inspect.Parameter.empty


def module_name(pyx: Path) -> str:
    return ".".join(("robkin", "compiled", *pyx.relative_to(COMPILED).with_suffix("").parts))


MODULES = {module_name(p): p for p in SOURCES}

# ---------------------------------------------------------------------------------------------------------
# What a stub declares (read with ast) and what a .pyx declares as a constructor (read as text)


def _literal(node: ast.expr | None) -> Any:
    if node is None:
        return NO_DEFAULT
    try:
        return ast.literal_eval(node)
    except ValueError:
        return f"<not a literal: {ast.unparse(node)}>"


def stub_params(args: ast.arguments) -> list[tuple[str, Any, Any]]:
    """(name, kind, default) of each parameter of a stub's function."""
    positional = [(a, KIND.POSITIONAL_ONLY) for a in args.posonlyargs]
    positional += [(a, KIND.POSITIONAL_OR_KEYWORD) for a in args.args]
    defaults = [None] * (len(positional) - len(args.defaults)) + list(args.defaults)
    out = [(a.arg, kind, _literal(d)) for (a, kind), d in zip(positional, defaults)]
    if args.vararg:
        out.append((args.vararg.arg, KIND.VAR_POSITIONAL, NO_DEFAULT))
    out += [(a.arg, KIND.KEYWORD_ONLY, _literal(d)) for a, d in zip(args.kwonlyargs, args.kw_defaults)]
    if args.kwarg:
        out.append((args.kwarg.arg, KIND.VAR_KEYWORD, NO_DEFAULT))
    return out


def real_params(obj: Any) -> list[tuple[str, Any, Any]]:
    return [(p.name, p.kind, p.default) for p in inspect.signature(obj).parameters.values()]


class StubClass:
    def __init__(self, node: ast.ClassDef):
        self.methods: dict[str, list[tuple[str, Any, Any]]] = {}
        self.attributes: set[str] = set()
        for item in node.body:
            if isinstance(item, ast.FunctionDef):
                if any(ast.unparse(d) == "property" for d in item.decorator_list):
                    self.attributes.add(item.name)
                else:
                    self.methods[item.name] = stub_params(item.args)
            elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                self.attributes.add(item.target.id)


class Stub:
    """The top-level declarations of a .pyi: functions, classes, annotated variables (``NAME: type``).
    A plain assignment (``Pose = tuple[...]``) is a type alias, not a module attribute."""

    def __init__(self, text: str):
        tree = ast.parse(text)
        self.functions: dict[str, list[tuple[str, Any, Any]]] = {}
        self.classes: dict[str, StubClass] = {}
        self.variables: set[str] = set()
        for node in tree.body:
            if isinstance(node, ast.FunctionDef):
                self.functions[node.name] = stub_params(node.args)
            elif isinstance(node, ast.ClassDef):
                self.classes[node.name] = StubClass(node)
            elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
                self.variables.add(node.target.id)

    def names(self) -> set[str]:
        return set(self.functions) | set(self.classes) | self.variables


def _split_top_level(text: str, sep: str) -> list[str]:
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == sep and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return parts


def cython_params(text: str) -> list[tuple[str, Any, Any]]:
    """(name, kind, default) of a Cython ``def`` parameter list: ``Chain chain, double scale, int threads=0``."""
    out: list[tuple[str, Any, Any]] = []
    keyword_only = False
    for token in _split_top_level(text, ","):
        token = token.strip()
        if not token:
            continue
        if token == "*":
            keyword_only = True
            continue
        if token.startswith("**"):
            out.append((token[2:].strip(), KIND.VAR_KEYWORD, NO_DEFAULT))
            continue
        if token.startswith("*"):
            out.append((token[1:].strip(), KIND.VAR_POSITIONAL, NO_DEFAULT))
            keyword_only = True
            continue
        head, *default = _split_top_level(token, "=")
        head = re.sub(r"\s+(not|or)\s+None$", "", head.strip())
        name = re.findall(r"\w+", head)[-1]
        value = _literal(ast.parse(default[0].strip(), mode="eval").body) if default else NO_DEFAULT
        out.append((name, KIND.KEYWORD_ONLY if keyword_only else KIND.POSITIONAL_OR_KEYWORD, value))
    return out


_TOP_LEVEL = re.compile(r"(cdef|cpdef|def|class|from|import|include|ctypedef|@|[A-Za-z_]\w*\s*[=:(])")


def source_constructors(pyx: Path) -> dict[str, list[tuple[str, Any, Any]]]:
    """class name -> the parameters of its ``def __init__`` (else ``def __cinit__``) in the .pyx."""
    found: dict[str, dict[str, str]] = {}
    lines = pyx.read_text().splitlines()
    current = None
    for i, line in enumerate(lines):
        header = re.match(r"cdef class (\w+)", line)
        if header:
            current = header[1]
            continue
        if line[:1].strip() and _TOP_LEVEL.match(line):
            current = None
        method = re.match(r"    def (__init__|__cinit__)\(", line)
        if current and method:
            text = "\n".join(lines[i:])
            start = text.index("(") + 1
            depth, end = 1, start
            while depth:
                depth += {"(": 1, ")": -1}.get(text[end], 0)
                end += 1
            params = re.sub(r"#[^\n]*", "", text[start:end - 1])
            found.setdefault(current, {})[method[1]] = params
    return {cls: cython_params(m.get("__init__", m.get("__cinit__", ""))) for cls, m in found.items()}


def constructor(cls: type) -> list[tuple[str, Any, Any]] | None:
    """The constructor's parameters of a compiled class: its own ``__init__`` if Python can read it, else
    the nearest declaration in the .pyx along the MRO; None: no constructor declared (object's)."""
    try:
        init = cls.__init__
        if inspect.isfunction(init) or type(init).__name__ == "cython_function_or_method":
            return real_params(init)
    except (TypeError, ValueError):
        pass
    for base in cls.__mro__:
        pyx = MODULES.get(getattr(base, "__module__", ""))
        if pyx is not None:
            params = source_constructors(pyx).get(base.__name__)
            if params is not None:
                return params
    return None


# ---------------------------------------------------------------------------------------------------------
# The comparison


def _compare(where: str, declared: list[tuple[str, Any, Any]], actual: list[tuple[str, Any, Any]]) -> list[str]:
    if declared == actual:
        return []

    def show(params: list[tuple[str, Any, Any]]) -> str:
        return ", ".join(f"{n}{'' if d is NO_DEFAULT else '=...' if d is Ellipsis else '=' + repr(d)}"
                         f"{'' if k == KIND.POSITIONAL_OR_KEYWORD else ' [' + k.name + ']'}" for n, k, d in params)

    return [f"{where}: the stub says ({show(declared)}), the module has ({show(actual)})"]


def stub_problems(module: Any, stub: Stub) -> list[str]:
    """Every disagreement between a module and its stub, one line each."""
    problems: list[str] = []
    name = module.__name__
    for fname, params in stub.functions.items():
        obj = getattr(module, fname, None)
        if not callable(obj):
            problems.append(f"{name}.{fname}: declared in the stub, not a function of the module")
            continue
        problems += _compare(f"{name}.{fname}", params, real_params(obj))
    for var in stub.variables:
        if not hasattr(module, var):
            problems.append(f"{name}.{var}: declared in the stub, not in the module")
    for cname, declared in stub.classes.items():
        cls = getattr(module, cname, None)
        if not inspect.isclass(cls):
            problems.append(f"{name}.{cname}: declared in the stub, not a class of the module")
            continue
        for mname, params in declared.methods.items():
            if mname == "__init__":
                actual = constructor(cls)
                if actual is None:
                    problems.append(f"{name}.{cname}.__init__: declared in the stub, the class has no constructor")
                else:
                    problems += _compare(f"{name}.{cname}.__init__", params, actual)
                continue
            obj = getattr(cls, mname, None)
            if not callable(obj):
                problems.append(f"{name}.{cname}.{mname}: declared in the stub, not a method of the class")
                continue
            problems += _compare(f"{name}.{cname}.{mname}", params, real_params(obj))
        for attr in declared.attributes:
            if not hasattr(cls, attr):
                problems.append(f"{name}.{cname}.{attr}: declared in the stub, not an attribute of the class")
        # what the class itself defines for Python: its public methods, and a constructor of its own
        for mname, obj in vars(cls).items():
            if not mname.startswith("_") and callable(obj) and mname not in declared.methods:
                problems.append(f"{name}.{cname}.{mname}: a method of the class, missing from the stub")
        pyx = MODULES.get(getattr(cls, "__module__", ""))
        if pyx is not None and cname in source_constructors(pyx) and "__init__" not in declared.methods:
            problems.append(f"{name}.{cname}.__init__: the class has a constructor, missing from the stub")
    for pname, obj in vars(module).items():
        if pname.startswith("_") or getattr(obj, "__module__", None) != name:
            continue
        if inspect.isclass(obj) and pname not in stub.classes:
            problems.append(f"{name}.{pname}: a class of the module, missing from the stub")
        elif not inspect.isclass(obj) and callable(obj) and pname not in stub.functions:
            problems.append(f"{name}.{pname}: a function of the module, missing from the stub")
    return sorted(problems)


# ---------------------------------------------------------------------------------------------------------
# The tests


def test_every_extension_has_a_stub_beside_it():
    assert len(SOURCES) >= 25, f"found only {len(SOURCES)} .pyx files under {COMPILED}"
    missing = [str(p.relative_to(COMPILED)) for p in SOURCES if not p.with_suffix(".pyi").is_file()]
    assert not missing, "compiled modules without a .pyi stub beside them: " + ", ".join(missing)


def _import(name: str) -> Any:
    if name.endswith("_avx2"):
        # never imported on a CPU without AVX2 (its initialisation may use it); absent when not built
        from robkin.compiled.chain import kernels

        if not (kernels.cpu_has_avx2() and kernels.avx2_built()):
            pytest.skip(f"{name}: this CPU has no AVX2 or the build has no AVX2 kernels")
    return importlib.import_module(name)


@pytest.mark.parametrize("name", sorted(MODULES))
def test_stub_declares_what_the_module_has(name):
    module = _import(name)
    stub = MODULES[name].with_suffix(".pyi")
    assert stub.is_file(), f"{name}: no stub {stub.name} beside {MODULES[name].name}"
    problems = stub_problems(module, Stub(stub.read_text()))
    assert not problems, f"{stub.relative_to(COMPILED)} does not match {name}:\n" + "\n".join(problems)


def test_a_drifted_stub_is_refused():
    """The comparison itself: a stub with a wrong default, a renamed and a missing parameter, a function and
    a class the module lacks, a method missing from its class and a wrong constructor is refused, line by line."""
    from robkin.compiled.chain import fk

    stub = Stub('''
class Chain:
    n: int
    missing_attribute: int
    def __init__(self, L, joint_types) -> None: ...
    def fk(self, q, threads=1, out=None): ...
def sincos(angles): ...
def not_in_the_module(x): ...
class NotAClass: ...
''')
    problems = stub_problems(fk, stub)
    expected = ["Chain.__init__: the stub says (self, L, joint_types)",
                "Chain.fk: the stub says (self, q, threads=1, out=None), the module has (self, q, threads=0",
                "Chain.frames: a method of the class, missing from the stub",
                "Chain.missing_attribute: declared in the stub, not an attribute",
                "sincos: the stub says (angles), the module has (x)",
                "not_in_the_module: declared in the stub, not a function",
                "NotAClass: declared in the stub, not a class"]
    for text in expected:
        assert any(text in p for p in problems), (text, problems)
    assert len(problems) == len(expected), problems
    assert stub_problems(fk, Stub(MODULES["robkin.compiled.chain.fk"].with_suffix(".pyi").read_text())) == []


def test_cython_parameter_lists_are_read():
    assert cython_params("self, Chain chain not None, double scale, cnp.ndarray[double, ndim=2] A, "
                         "int threads=0, *, str method='x'") == [
        ("self", KIND.POSITIONAL_OR_KEYWORD, NO_DEFAULT), ("chain", KIND.POSITIONAL_OR_KEYWORD, NO_DEFAULT),
        ("scale", KIND.POSITIONAL_OR_KEYWORD, NO_DEFAULT), ("A", KIND.POSITIONAL_OR_KEYWORD, NO_DEFAULT),
        ("threads", KIND.POSITIONAL_OR_KEYWORD, 0), ("method", KIND.KEYWORD_ONLY, "x")]
