"""The IK result as text: what ``str(result)`` shows and ``robkin ik`` prints.

One row per target (success, errors, q), or with ``solutions`` of one target one row per solution;
laid out with the generic blocks of ``robkin.io.tables.text``.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from ..io.tables.text import Block

__all__ = ["MAX_ROWS", "solutions_block", "ik_result_blocks"]

#: Rows of a batch IK result shown by str(); a batch of 1e5 targets stays a screenful.
MAX_ROWS = 20


def solutions_block(solutions: np.ndarray, method: str, names: Sequence[str]) -> Block:
    """IK solutions (S, n) of one target as a table, one row per solution (as ``robkin ik`` prints)."""
    rows = [[str(i + 1), *s] for i, s in enumerate(solutions)]
    return (f"IK solutions ({method}, nearest to q0 first)", ["#", *names], rows)


def ik_result_blocks(result: Any, names: Sequence[str] | None = None) -> list[Block]:
    """An IK result: with ``solutions`` of one target, one row per solution; otherwise one row per
    target with its success, errors and q (the best configuration found where it failed).

    ``result`` is an ``IKResult`` (not imported here: ``ik`` imports this module for its ``__str__``).
    """
    q = np.asarray(result.q, dtype=float)
    n = q.shape[-1]
    names = list(names) if names is not None else [f"q{i + 1}" for i in range(n)]
    if q.ndim == 1 and isinstance(result.solutions, np.ndarray) and len(result.solutions):
        return [solutions_block(result.solutions, result.method, names)]
    Q = q.reshape(-1, n)
    success = np.broadcast_to(result.success, Q.shape[:1])
    pos = np.broadcast_to(result.position_error, Q.shape[:1])
    rot = np.broadcast_to(result.orientation_error, Q.shape[:1])
    messages = [result.message] * len(Q) if isinstance(result.message, str) else list(result.message)
    shown = range(min(len(Q), MAX_ROWS))
    rows = [[str(i + 1), "yes" if success[i] else "no", float(pos[i]), float(rot[i]), *Q[i]] for i in shown]
    out: list[Block] = [(f"IK ({result.method}): {int(np.sum(success))} of {len(Q)} reached",
                         ["#", "success", "position error", "orientation error", *names], rows)]
    if len(Q) > MAX_ROWS:
        out.append(f"... {len(Q) - MAX_ROWS} more targets (the arrays of the result hold them all)")
    out += [f"target {i + 1}: {messages[i]}" for i in shown if messages[i]]
    return out
