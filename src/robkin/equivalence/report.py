"""The comparison as text: what ``str(comparison)`` shows and ``robkin check`` prints.

The joint-by-joint diagnosis of ``equivalence.compare``: per-joint table, tool, world, FK difference,
verdict; laid out with the generic blocks of ``robkin.io.tables.text``.
"""

from __future__ import annotations

import math
from typing import Any

from ..io.tables.text import Block

__all__ = ["comparison_blocks"]


def comparison_blocks(c: Any, title: str | None = None) -> list[Block]:
    """The diagnosis of ``equivalence.compare``: per-joint table, tool, world, FK difference, verdict.

    ``c`` is a ``Comparison`` (not imported here: ``comparison`` imports this module for its ``__str__``).
    """
    rows = [[str(j.index + 1), j.name_a, j.name_b, j.type_a if j.type_a == j.type_b else f"{j.type_a}/{j.type_b}",
             j.status, "-" if j.sign < 0 else "+", j.offset, j.detail] for j in c.joints]
    title = title or f"A ({c.n_a} joints) vs B ({c.n_b} joints)"
    out: list[Block] = []
    if c.n_a != c.n_b:  # the answer first: no joint-by-joint detail changes it
        out.append(f"verdict: {c.verdict()}")
    out += [(title, ["joint", "A", "B", "type", "status", "sign", "offset", "how"], rows),
            f"tool:  {c.tool}", f"world: {c.world}"]
    if math.isfinite(c.max_fk_error):
        what = "under the joint mapping" if c.equivalent and not c.same else "at the same q"
        out.append(f"largest FK difference at 64 random q {what}: {c.max_fk_error:.3g} (relative to robot size)")
    out += [f"note: {note}" for note in c.notes]
    if c.n_a == c.n_b:
        out.append(f"verdict: {c.verdict()}")
    return out
