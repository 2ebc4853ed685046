"""The robot document's vocabulary, shared by its reader (``reader``) and writer (``writer``): section
names, which columns are angles, the document version.

The sections and their columns come from the registry of representations
(``robkin.representations.registry``): ``SECTIONS`` and ``ANGLE_COLUMNS`` are live views of it, so a
registered representation is a section documents read and write.
"""

from __future__ import annotations

from ...representations.registry import LiveMapping, LiveNames, representations, sections

__all__ = ["SECTIONS", "DOC_VERSION", "ANGLE_COLUMNS", "ANGLE_UNITS"]

#: Representation sections, in the order that decides which one defines the GJD when several are given.
SECTIONS = LiveNames(sections)
DOC_VERSION = 1
#: Which columns of each section's rows are angles (converted for ``angles: degrees``).
ANGLE_COLUMNS = LiveMapping(lambda: {r.section: r.angle_keys for r in representations()
                                     if r.layout in ("link-table", "rpy")})
ANGLE_UNITS = ("radians", "degrees")
