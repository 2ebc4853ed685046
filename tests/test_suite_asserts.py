"""The test suite's own hygiene: every test checks something that can fail.

Two patterns that once let tests pass without checking anything (issue "A release anyone can trust"):
a test function that ``return``s before asserting (a property test returned early on 45 of its 60
drawn arms), and a comparison of a value with itself (a README example's Jacobian compared with
``robot.jacobian(q)``, the very call that made it). Filter examples with ``hypothesis.assume``; end a
test early only right after an assertion.
"""

from __future__ import annotations

import ast
from pathlib import Path

TESTS = Path(__file__).parent
#: calls that check (or end the test on purpose) and so may come right before a ``return``
CHECKS = ("assert", "pytest.fail", "pytest.skip", "pytest.xfail", "raises")


def _test_functions():
    for path in sorted(TESTS.glob("test_*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name.startswith("test"):
                yield path.name, node


def _checks(stmt: ast.stmt) -> bool:
    if isinstance(stmt, ast.Assert):
        return True
    return isinstance(stmt, ast.Expr) and isinstance(stmt.value, ast.Call) and \
        any(c in ast.unparse(stmt.value.func) for c in CHECKS)


def _early_returns(fn: ast.FunctionDef | ast.AsyncFunctionDef) -> list[int]:
    """Lines of ``return`` statements of fn (not of functions nested in it) that do not directly follow
    a check in their block."""
    bad, blocks = [], [fn.body]
    while blocks:
        block = blocks.pop()
        for i, stmt in enumerate(block):
            if isinstance(stmt, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                continue
            if isinstance(stmt, ast.Return) and not (i > 0 and _checks(block[i - 1])):
                bad.append(stmt.lineno)
            for field in ("body", "orelse", "finalbody"):
                inner = getattr(stmt, field, None)
                if isinstance(inner, list) and inner and isinstance(inner[0], ast.stmt):
                    blocks.append(inner)
            for handler in getattr(stmt, "handlers", []):
                blocks.append(handler.body)
            for case in getattr(stmt, "cases", []):
                blocks.append(case.body)
    return bad


def test_no_test_returns_before_asserting():
    found = [f"{name}:{line} {fn.name}" for name, fn in _test_functions() for line in _early_returns(fn)]
    assert found == [], "a test returns before asserting (use hypothesis.assume or pytest.skip): " + \
        ", ".join(found)


def test_no_value_is_compared_with_itself():
    found = []
    for name, fn in _test_functions():
        for node in ast.walk(fn):
            if isinstance(node, ast.Compare) and len(node.ops) == 1 and \
                    not isinstance(node.ops[0], (ast.Is, ast.IsNot)) and \
                    ast.dump(node.left) == ast.dump(node.comparators[0]):
                found.append(f"{name}:{node.lineno} {ast.unparse(node)}")
            if isinstance(node, ast.Call) and len(node.args) >= 2 and \
                    any(k in ast.unparse(node.func) for k in ("allclose", "array_equal", "approx", "isclose")) \
                    and ast.dump(node.args[0]) == ast.dump(node.args[1]):
                found.append(f"{name}:{node.lineno} {ast.unparse(node)[:80]}")
    assert found == [], "compared with itself: " + ", ".join(found)


def test_the_scans_find_what_they_look_for():
    # the scans themselves can fail: a test that returns first, one that returns after a check
    early = ast.parse("def test_a(x):\n    if x:\n        return\n    assert x\n").body[0]
    after = ast.parse("def test_b(x):\n    assert x\n    return\n").body[0]
    assert _early_returns(early) == [3] and _early_returns(after) == []
