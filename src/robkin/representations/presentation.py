"""The representations' facade to io: a table's text and its robot document.

``str(table)`` and ``table.to_dict()`` of every table class (``LinkTable``, ``PoE``, ``RPYTable``)
come here; the layouts themselves live where text and documents are made (``robkin.io.tables.views``,
``robkin.io.documents.writer``), driven by the registry (``robkin.representations.registry``). This
module is the representations layer's one declared way up (``tests/test_architecture.py``, FACADES):
it imports io lazily, inside each function, when a table is printed or written.
"""

from __future__ import annotations

from typing import Any

__all__ = ["table_text", "table_document"]


def table_text(table: Any) -> str:
    """``str()`` of a table: its blocks as plain text, titled with its representation's description."""
    from ..io.tables.views import table_text as text

    return text(table)


def table_document(table: Any) -> dict[str, Any]:
    """``to_dict()`` of a table: a robot document (dict) with ``joints`` and the table's section."""
    from ..io.documents.writer import table_document as document

    return document(table)
