"""The GUI's bare-table formats: they live in ``robkin.io.tables.pasted`` (the CLI reads them too)."""

from __future__ import annotations

from ..io.tables.pasted import TABLE_FORMATS, document_from_table

__all__ = ["TABLE_FORMATS", "document_from_table"]
