"""Text cells of written tables made inert: CSV against spreadsheet formulas, Markdown against HTML.

A table's text cells (joint names, frame names, types, the title) come from an untrusted robot file.

* CSV (OWASP "CSV injection"): a spreadsheet runs a cell beginning with ``=``, ``+``, ``-`` or ``@``
  (and, in some, a tab or carriage return before one) as a formula. :func:`csv_text_cell` prefixes
  such a text cell with a single quote ``'`` (spreadsheets show the rest as text); a name that already
  begins with quotes followed by one of those gets one more, so :func:`csv_read_cell` (the table
  reader's) gives back exactly the name written. Number cells are never passed through it: ``-1.5``
  stays a number.
* Markdown: :func:`md_text_cell` escapes ``& < >`` as HTML entities (no tag, comment or entity of the
  name reaches the page) and backslash-escapes what would make links, images, emphasis, code or a
  table cell boundary (``\\ | [ ] * ` ~``, and ``_`` but inside a word, where it emphasises nothing:
  ``shoulder_pan_joint`` stays as it is), so a name renders as its own characters.
"""

from __future__ import annotations

__all__ = ["FORMULA_STARTS", "csv_text_cell", "csv_read_cell", "md_text_cell"]

#: First characters a spreadsheet takes as the start of a formula (or of a cell it then re-reads).
FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r")
_MD_PUNCT = "\\|[]*`~"
_HTML = {"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;"}


def csv_text_cell(s: str) -> str:
    """``s`` as a CSV text cell no spreadsheet runs: ``'`` before it when it (after any quotes) starts
    a formula. Inverse: :func:`csv_read_cell`."""
    return "'" + s if s.lstrip("'").startswith(FORMULA_STARTS) else s


def csv_read_cell(s: str) -> str:
    """A text cell as robkin wrote it, back to the original (one ``'`` dropped before a formula
    start, after any further quotes); other cells unchanged."""
    return s[1:] if s.startswith("'") and s[1:].lstrip("'").startswith(FORMULA_STARTS) else s


def md_text_cell(s: str) -> str:
    """``s`` for a Markdown table cell: HTML special characters as entities, Markdown syntax escaped."""
    out = []
    for k, c in enumerate(s):
        if c == "_":  # emphasis only at a word's edge (CommonMark's intraword rule)
            inside = 0 < k < len(s) - 1 and s[k - 1].isalnum() and s[k + 1].isalnum()
            out.append(c if inside else "\\_")
        else:
            out.append(_HTML.get(c) or ("\\" + c if c in _MD_PUNCT else c))
    return "".join(out)
