"""Lint of the formats other than URDF (MJCF, SDF, USD, robot documents, tables): their strict readers'
checks. A reader's refusal is a finding (error, with the line when the reader names one); a file that is
not there, too big or not parseable at all stays an ``InputError``. The full per-link checks are URDF's."""

from __future__ import annotations

import re
from pathlib import Path

from ..errors import InputError
from .findings import ERROR, INFO, Finding

__all__ = ["lint_other"]

#: reader messages that mean "cannot be read at all" (exit 2), not "read, and wrong" (a finding)
_UNREADABLE = re.compile(r"no such file|not a regular file|larger than|not well-formed|not valid XML|is empty|"
                         r"refused XML|cannot be read|not a file|unknown (?:file )?(?:type|format|extension)|"
                         r"permission", re.I)
_LINE = re.compile(r"\bline (\d+)")


def lint_other(path: str, allow_xacro: bool = False) -> list[Finding]:
    from ..io import load

    p = Path(path)
    if not p.is_file():
        raise InputError(f"{path}: no such file")
    try:
        robot = load(path, allow_xacro=allow_xacro)
    except InputError as exc:
        msg = str(exc)
        if _UNREADABLE.search(msg):
            raise
        m = _LINE.search(msg)
        text = msg[len(path) + 2:] if msg.startswith(path + ": ") else msg
        return [Finding(ERROR, "reader-refuses", path, int(m.group(1)) if m else None, "", text,
                        "correct what the message names")]
    found = []
    for j in robot.joints:
        if j.lower is not None and j.upper is not None and j.lower > j.upper:
            found.append(Finding(ERROR, "limits-reversed", path, None, f"joint '{j.name}'",
                                 f"lower {j.lower:g} > upper {j.upper:g}", "swap them"))
    found.append(Finding(INFO, "format-checks", path, None, "",
                         f"{p.suffix} files get their reader's checks and the joint limits; the per-link mass, "
                         "asset and structure checks are URDF's", "convert to URDF (robkin convert --to urdf) "
                         "and lint that for the full checks"))
    return found
