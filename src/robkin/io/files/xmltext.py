"""Quoting XML attribute values for the URDF and MJCF writers.

Hand-written because ``xml.sax.saxutils.quoteattr`` imports ``urllib.request`` (and with it
``http.client`` and ``email``), which would add tens of milliseconds to every ``robkin convert``.
"""

from __future__ import annotations

__all__ = ["quoteattr"]

_ESCAPES = {"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "\n": "&#10;", "\r": "&#13;", "\t": "&#9;"}


def quoteattr(value: str) -> str:
    """``value`` escaped and wrapped in double quotes, ready to follow ``name=`` in an XML tag."""
    return '"' + "".join(_ESCAPES.get(c, c) for c in str(value)) + '"'
