"""The ``<contact>`` section of a written MJCF: body pairs excluded from contact (``<exclude>``).

The pairs are data the caller gives the writer (``robkin.collision.exclusions`` finds them: parent-child
pairs and pairs touching at home); names are quoted as every other name copied from the input.
"""

from __future__ import annotations

from typing import Sequence

from ..files.xmltext import quoteattr

__all__ = ["contact_lines"]


def contact_lines(excludes: Sequence[tuple[str, str]] | None) -> list[str]:
    """``<contact>`` with one ``<exclude>`` per body pair (nothing for no pairs)."""
    if not excludes:
        return []
    return (["  <contact>"] + [f"    <exclude body1={quoteattr(a)} body2={quoteattr(b)}/>" for a, b in excludes]
            + ["  </contact>"])
