"""The robot document's vocabulary, shared by its reader (``document``) and writer (``document_write``):
section names, row keys, which columns are angles, the document version."""

from __future__ import annotations

__all__ = ["SECTIONS", "DOC_VERSION", "DH_KEYS", "RPY_KEYS", "HAYATI_KEYS", "ANGLE_COLUMNS", "ANGLE_UNITS"]

#: Representation sections, in the order that decides which one defines the GJD when several are given.
SECTIONS = ("gjd", "dh", "mdh", "hayati", "rpy_xyz", "poe", "poe_body")
DOC_VERSION = 1
DH_KEYS = ("a", "d", "alpha", "theta")
RPY_KEYS = ("roll", "pitch", "yaw", "x", "y", "z")
HAYATI_KEYS = ("a", "d", "alpha", "theta", "beta")
#: Which columns of each section's rows are angles (converted for ``angles: degrees``).
ANGLE_COLUMNS = {"dh": ("alpha", "theta"), "mdh": ("alpha", "theta"), "hayati": ("alpha", "theta", "beta"),
                 "rpy_xyz": ("roll", "pitch", "yaw")}
ANGLE_UNITS = ("radians", "degrees")
