"""``robkin lint --fix`` of an SDF file: changed only where lint reported something it can correct, one line
per change; comments and layout elsewhere kept. The corrections are MJCF's (``fix_mjcf``, one
implementation of each: ``_fix_mass``), written the SDF way:

- ``<axis><limit>`` with lower > upper: ``<lower>`` and ``<upper>`` swapped;
- ``<axis><xyz>`` not of unit length: normalised;
- an ``<inertial>`` not positive definite, breaking the triangle inequality or singular: the nearest valid
  tensor, or the collision geometry's at the link's mass (``--inertia geometry``, which also replaces
  placeholder inertias and inertias the geometry cannot hold);
- a moving link without ``<inertial>`` (SDFormat's default 1 kg and unit inertia, ``mass-default``) or
  without mass: an ``<inertial>`` of its collision geometry at ``density``.

A new ``<inertial>`` is ``<pose>`` (the centre of mass, no rotation) + ``<mass>`` + ``<inertia>`` in the link
frame. Links of nested models are found by their scoped name (``inner::link``).
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from .findings import Finding
from .fix_mjcf import _fix_mass, _num, fixable, parse_keeping_comments, written
from .fix_urdf import _GEOMETRY_ONLY, _INERTIA_CODES
from .geometry import MeshCache
from .urdf_source import RawUrdf

__all__ = ["fix_sdf"]


def _sub(parent: Any, tag: str, text: str) -> Any:
    from lxml import etree  # type: ignore[import-untyped, unused-ignore]

    el = etree.SubElement(parent, tag)
    el.text = text
    return el


def _write_inertial(link: Any, mass: float, com: np.ndarray, I: np.ndarray) -> None:
    """Replace (or add, first in the link after its ``<pose>``) the link's ``<inertial>``."""
    from lxml import etree  # type: ignore[import-untyped, unused-ignore]

    old = link.find("inertial")
    new = etree.Element("inertial")
    _sub(new, "pose", " ".join(_num(v) for v in com) + " 0 0 0")
    _sub(new, "mass", _num(mass))
    inertia = etree.SubElement(new, "inertia")
    for key, (r, c) in zip(("ixx", "iyy", "izz", "ixy", "ixz", "iyz"), ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))):
        _sub(inertia, key, _num(I[r, c]))
    if old is not None:
        new.tail = old.tail
        link.replace(old, new)
    else:
        kids = [c for c in link if isinstance(c.tag, str)]
        after = next((c for c in kids if c.tag == "pose"), None)
        new.tail = (after.tail if after is not None else link.text) or "\n"
        if after is not None:
            after.addnext(new)
        elif kids:
            kids[0].addprevious(new)
        else:
            link.append(new)


def fix_sdf(path: str, findings: Sequence[Finding], *, inertia: str = "nearest", density: float = 1000.0,
            raw: RawUrdf | None = None, meshes: MeshCache | None = None) -> tuple[str, list[str]]:
    """The corrected SDF text for the ``findings`` lint gave on ``path``, and one line per change.

    Parameters and result as ``fix_mjcf.fix_mjcf``.
    """
    from .xml_lines import sdf_lines

    if inertia not in ("nearest", "geometry"):
        raise ValueError(f"inertia={inertia!r}: nearest or geometry")
    text, root = parse_keeping_comments(path)
    lines = sdf_lines(root)
    links = {ln.name: ln for ln in raw.links} if raw is not None else {}
    meshes = meshes or MeshCache(path)
    changes: list[str] = []
    for f, name, where in fixable(findings):
        joint = lines.joints.get(name) if f.element.startswith("joint") else None
        link = lines.links.get(name) if f.element.startswith("link") else None
        limit = joint.find("axis/limit") if joint is not None else None
        xyz = joint.find("axis/xyz") if joint is not None else None
        if f.code == "limits-reversed" and limit is not None and limit.find("lower") is not None \
                and limit.find("upper") is not None:
            lo, hi = limit.find("lower"), limit.find("upper")
            lo.text, hi.text = hi.text, lo.text
            changes.append(f"{where}: limits swapped: lower {lo.text.strip()}, upper {hi.text.strip()}")
        elif f.code == "axis-not-unit" and xyz is not None and xyz.text:
            v = np.array([float(x) for x in xyz.text.split()])
            xyz.text = " ".join(_num(x) for x in v / np.linalg.norm(v))
            changes.append(f"{where}: axis normalised to {xyz.text}")
        elif f.code in _INERTIA_CODES + _GEOMETRY_ONLY + ("mass-zero-moving", "mass-default") and name in links \
                and link is not None:
            changes.append(_fix_mass(f, where, links[name], link, inertia, density, meshes, _write_inertial))
        elif f.severity == "error" or f.code in ("limits-zero-range", "effort-zero", "velocity-zero"):
            changes.append(f"{where}: not fixed ({f.code}): {f.fix}")
    return written(text, root), changes
