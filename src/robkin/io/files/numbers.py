"""Reading numbers the way people type them in robot tables: 0.2, -1.5708, or "-pi/2", "3*pi/4".

A tiny arithmetic evaluator over Python's ``ast`` (numbers, pi, tau, e, + - * / ** and parentheses).
Written by hand because ``eval`` is unsafe and a full expression library is far more than this needs.
"""

from __future__ import annotations

import ast
import math
import operator
from typing import Any

from ...compiled.scanners.vocabulary import MAX_ABS  # the one bound on any number of a robot description
from ...errors import InputError, quote
__all__ = ["number", "number_list", "matrix", "MAX_INT_DIGITS", "MAX_ABS"]

#: The YAML and JSON readers turn integers longer than this (in characters) into +-inf, which
#: ``number`` refuses naming the field: 400 digits are beyond the float range (1.8e308), and Python
#: refuses to convert integers of more than 4300 digits at all.
MAX_INT_DIGITS = 400

_NAMES = {"pi": math.pi, "tau": math.tau, "e": math.e}
_BINOPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
           ast.Div: operator.truediv, ast.Pow: operator.pow}
_UNOPS = {ast.UAdd: operator.pos, ast.USub: operator.neg}


def _eval(node: ast.AST) -> float:
    if isinstance(node, ast.Expression):
        return _eval(node.body)
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        return float(node.value)
    if isinstance(node, ast.Name) and node.id.lower() in _NAMES:
        return _NAMES[node.id.lower()]
    if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
        return _BINOPS[type(node.op)](_eval(node.left), _eval(node.right))
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNOPS:
        return _UNOPS[type(node.op)](_eval(node.operand))
    raise ValueError("unsupported expression")


def number(value: Any, field: str) -> float:
    """A finite float from a number or an arithmetic string such as "-pi/2"; InputError otherwise."""
    if isinstance(value, bool) or value is None:
        raise InputError(f"{field}: expected a number, got {quote(value)}")
    if isinstance(value, (int, float)):
        try:
            x = float(value)
        except OverflowError:  # an int beyond the float range
            x = math.inf
    elif isinstance(value, str):
        text = value.strip()
        if len(text) > 200:
            raise InputError(f"{field}: expression too long ({len(text)} characters; at most 200)")
        try:
            x = float(_eval(ast.parse(text, mode="eval")))
        except (SyntaxError, ValueError, ZeroDivisionError, OverflowError, TypeError, RecursionError,
                MemoryError):
            raise InputError(f"{field}: cannot read {quote(value)} as a number (numbers, pi, + - * / allowed)") from None
    else:
        raise InputError(f"{field}: expected a number, got {type(value).__name__}")
    if math.isnan(x):
        raise InputError(f"{field}: must be a finite number, got {quote(value)}")
    if not abs(x) <= MAX_ABS:
        raise InputError(f"{field}: must be a finite number of magnitude at most {MAX_ABS:g}, got {quote(value)}")
    return x


def number_list(value: Any, field: str, length: int | None = None) -> list[float]:
    """A list of numbers (a YAML/JSON list, or a comma-separated string); optional exact length."""
    if isinstance(value, str):
        items: list[Any] = [v for v in value.replace(";", ",").split(",")]
        if items and items[-1].strip() == "":
            items = items[:-1]
    elif isinstance(value, (list, tuple)):
        items = list(value)
    else:
        raise InputError(f"{field}: expected a list of numbers, got {type(value).__name__}")
    if length is not None and len(items) != length:
        raise InputError(f"{field}: expected {length} numbers, got {len(items)}")
    return [number(v, f"{field}[{i}]") for i, v in enumerate(items)]


def matrix(value: Any, field: str, shape: tuple[int, int] = (4, 4)) -> list[list[float]]:
    """A matrix given as a list of rows (or, for 4x4, 16 numbers row-major)."""
    rows, cols = shape
    if isinstance(value, (list, tuple)) and len(value) == rows * cols and not any(
            isinstance(v, (list, tuple)) for v in value):
        flat = number_list(value, field)
        return [flat[r * cols:(r + 1) * cols] for r in range(rows)]
    if not isinstance(value, (list, tuple)):
        raise InputError(f"{field}: expected a {rows}x{cols} matrix (list of rows)")
    if shape == (4, 4) and len(value) == 3:
        value = list(value) + [[0, 0, 0, 1]]
    if len(value) != rows:
        raise InputError(f"{field}: expected {rows} rows, got {len(value)}")
    return [number_list(r, f"{field}[{i}]", cols) for i, r in enumerate(value)]
