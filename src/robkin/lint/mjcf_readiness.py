"""Simulator readiness of an MJCF file: what MuJoCo itself refuses (its compiler's verdict, with its line),
and the ``<compiler>`` settings with which MuJoCo silently changes the mass properties that pinocchio and
drake (which read the file as written) keep.

MuJoCo is asked only when it is installed (``import mujoco``); it reads the model's mesh files, nothing
else. Its first error is one finding (MuJoCo stops at the first); lint's own checks name the others.
"""

from __future__ import annotations

import re
from typing import Any

from .findings import ERROR, WARNING, Finding
from .xml_lines import XmlLines

__all__ = ["mjcf_readiness", "mujoco_verdict"]

_MJ_LINE = re.compile(r"line (\d+)")
#: compiler attributes with which MuJoCo changes what the file says, and what each does
_SILENT = {
    "balanceinertia": ("true", "MuJoCo silently moves inertias that break the triangle inequality onto it; "
                       "pinocchio and drake get the values as written"),
    "boundmass": (None, "MuJoCo silently raises every body's mass to at least {v} kg; pinocchio and drake "
                  "get the masses as written"),
    "boundinertia": (None, "MuJoCo silently raises every principal moment to at least {v} kg m^2; pinocchio "
                     "and drake get the inertias as written"),
    "inertiafromgeom": ("true", "MuJoCo replaces every <inertial> by the mass of the body's geoms; pinocchio "
                        "and drake read the <inertial>s"),
}


def mujoco_verdict(path: str) -> str | None:
    """MuJoCo's compile error of the file (None: it compiles, or MuJoCo is not installed)."""
    try:
        import mujoco  # type: ignore[import-not-found, unused-ignore]
    except ImportError:
        return None
    try:
        mujoco.MjModel.from_xml_path(str(path))
    except Exception as exc:  # MuJoCo raises ValueError with its compiler's message
        return " ".join(str(exc).split())
    return None


def mjcf_readiness(path: str, lines: XmlLines) -> list[Finding]:
    f: list[Finding] = []
    for el in lines.compiler:
        for key, (bad, what) in _SILENT.items():
            v = el.get(key)
            if v is None:
                continue
            changes = v == bad if bad else _positive(v)
            if changes:
                f.append(Finding(WARNING, f"mujoco-{key}", path, XmlLines.line(el), "compiler",
                                 f"{key}=\"{v}\": " + what.format(v=v),
                                 f"remove {key} and write the mass properties MuJoCo should use (robkin lint names "
                                 "the invalid ones)"))
    err = mujoco_verdict(path)
    if err is not None:
        m = _MJ_LINE.search(err)
        f.append(Finding(ERROR, "mujoco-refuses", path, int(m.group(1)) if m else None, "",
                         f"MuJoCo refuses the file: {err[:300]}", "correct what MuJoCo names"))
    return f


def _positive(text: Any) -> bool:
    try:
        return float(text) > 0
    except (TypeError, ValueError):
        return False
