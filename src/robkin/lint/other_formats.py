"""Lint of the formats other than URDF (MJCF, SDF, USD, robot documents, tables): their strict readers'
checks. A reader's refusal is a finding (error, with the line of the element it names), its warnings
(a near-valid value projected) are warnings; a file that is not there, too big or not parseable at all
stays an ``InputError``. The full per-link checks are URDF's."""

from __future__ import annotations

import re
from pathlib import Path

from ..errors import InputError
from .findings import ERROR, INFO, WARNING, Finding

__all__ = ["lint_other"]

#: reader messages that mean "cannot be read at all" (exit 2), not "read, and wrong" (a finding)
_UNREADABLE = re.compile(r"no such file|not a regular file|larger than|not well-formed|not valid XML|is empty|"
                         r"refused XML|cannot be read|not a file|unknown (?:file )?(?:type|format|extension)|"
                         r"permission", re.I)
_LINE = re.compile(r"\bline (\d+)")
#: the element a reader's message starts with: "joint 'j1' (body 'b1'): ..."
_ELEMENT = re.compile(r"^(joint|link|body|site|geom|model|mesh) '([^']{1,200})'")


def _line_of_name(path: str, name: str) -> int | None:
    """The first line of an XML file with name="NAME" (the reader keeps no lines; this finds the element)."""
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            for k, text in enumerate(fh, 1):
                if f'name="{name}"' in text or f"name='{name}'" in text:
                    return k
    except OSError:
        return None
    return None


def lint_other(path: str, allow_xacro: bool = False) -> list[Finding]:
    from ..io import load

    p = Path(path)
    if not p.is_file():
        raise InputError(f"{path}: no such file")
    import warnings

    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            robot = load(path, allow_xacro=allow_xacro)
    except InputError as exc:
        msg = str(exc)
        if _UNREADABLE.search(msg):
            raise
        m = _LINE.search(msg)
        text = msg[len(path) + 2:] if msg.startswith(path + ": ") else msg
        e = _ELEMENT.match(text)
        line = int(m.group(1)) if m else (_line_of_name(path, e.group(2)) if e and p.suffix.lower() in
                                          (".xml", ".mjcf", ".sdf") else None)
        return [Finding(ERROR, "reader-refuses", path, line, f"{e.group(1)} '{e.group(2)}'" if e else "",
                        text[e.end():].lstrip(" :") if e else text, "correct what the message names")]
    # what the reader changed silently but for a warning (a near-valid value projected, a mesh left out)
    found = [Finding(WARNING, "reader-changes", path, None, "", str(w.message).splitlines()[0],
                     "write the value the reader used (the message names it)") for w in caught
             if issubclass(w.category, UserWarning)]
    for j in robot.joints:
        if j.lower is not None and j.upper is not None and j.lower > j.upper:
            found.append(Finding(ERROR, "limits-reversed", path, None, f"joint '{j.name}'",
                                 f"lower {j.lower:g} > upper {j.upper:g}", "swap them"))
    found.append(Finding(INFO, "format-checks", path, None, "",
                         f"{p.suffix} files get their reader's checks and the joint limits; the per-link mass, "
                         "asset and structure checks are URDF's", "convert to URDF (robkin convert --to urdf) "
                         "and lint that for the full checks"))
    return found
