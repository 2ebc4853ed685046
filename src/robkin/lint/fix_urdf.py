"""``robkin lint --fix``: a URDF changed only where lint reported something it can correct, one line per change.

What is fixed: reversed limits (swapped), axes not of unit length (normalised), mimic targets that are
missing or cyclic (the ``<mimic>`` removed), inertias that are not positive definite, break the triangle
inequality or are singular (the nearest valid tensor, or the collision geometry's at the link's mass:
``inertia="nearest"|"geometry"``), placeholder inertias and inertias the geometry cannot hold (too large,
or nearly a point mass) with ``inertia="geometry"`` only, and moving links
without mass (mass, centre and inertia of the collision geometry at ``density``). Everything else is
left as written, and said ("not fixed: ..."). A new inertia is written in the link frame's axes (the
``<inertial><origin rpy>`` becomes 0 0 0; the centre of mass keeps its place).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from .findings import Finding
from .geometry import MeshCache, link_solid
from .mass_checks import principal
from .urdf_source import RawUrdf

__all__ = ["fix_urdf", "nearest_inertia", "FIXABLE"]

_INERTIA_CODES = ("inertia-not-positive", "inertia-triangle", "inertia-singular")
#: valid inertias that only --inertia geometry replaces (they look wrong against the geometry)
_GEOMETRY_ONLY = ("inertia-placeholder", "inertia-too-large", "inertia-vs-geometry")
FIXABLE = ("limits-reversed", "axis-not-unit", "mimic-missing", "mimic-cycle", "mass-zero-moving") + \
    _INERTIA_CODES + _GEOMETRY_ONLY
#: the smallest principal moment a fixed inertia gets, relative to its largest (and at least the mass times
#: (1 mm)^2): far above MuJoCo's mjMINVAL and drake's tolerance, far below any real link's moments
FLOOR_REL = 1e-6
FLOOR_GYRATION = 1e-3  # m
#: the fixed moments satisfy A + B >= (1 + TRIANGLE_MARGIN) C, so that rounding in the written file keeps them valid
TRIANGLE_MARGIN = 1e-6


def nearest_inertia(I: np.ndarray, mass: float) -> np.ndarray:
    """The nearest (principal moments moved least, axes kept) positive definite tensor whose moments satisfy
    the triangle inequality with a margin: moments clipped to a floor, then projected onto A + B >= C."""
    w, R = principal(I)
    floor = max(FLOOR_REL * float(abs(w).max()), mass * FLOOR_GYRATION ** 2, 1e-12)
    w = np.maximum(w, floor)
    for _ in range(3):
        order = np.argsort(w)
        a, b, c = w[order]
        gap = (1 + TRIANGLE_MARGIN) * c - a - b
        if gap <= 0:
            break
        d = gap / (3 + TRIANGLE_MARGIN)  # Euclidean projection onto the plane a + b - (1 + margin) c = 0
        w[order] = (a + d, b + d, c - d * (1 + TRIANGLE_MARGIN))
    return R @ np.diag(w) @ R.T


def _num(x: float) -> str:
    return repr(float(x))


def _write_inertial(ln, mass: float, com: np.ndarray, I: np.ndarray) -> None:
    from lxml import etree  # type: ignore[import-untyped, unused-ignore]

    inertial = ln.el.find("inertial")
    if inertial is None:
        inertial = etree.SubElement(ln.el, "inertial")
    origin = inertial.find("origin")
    if origin is None:
        origin = etree.SubElement(inertial, "origin")
    origin.set("xyz", " ".join(_num(v) for v in com))
    origin.set("rpy", "0 0 0")
    m = inertial.find("mass")
    if m is None:
        m = etree.SubElement(inertial, "mass")
    m.set("value", _num(mass))
    i = inertial.find("inertia")
    if i is None:
        i = etree.SubElement(inertial, "inertia")
    for key, (r, c) in zip(("ixx", "iyy", "izz", "ixy", "iyz", "ixz"), ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))):
        i.set(key, _num(I[r, c]))


def fix_urdf(u: RawUrdf, findings: Sequence[Finding], *, inertia: str = "nearest", density: float = 1000.0,
             meshes: MeshCache | None = None) -> tuple[str, list[str]]:
    """The corrected URDF for the ``findings`` lint gave on ``u``, and one line per change.

    Parameters
    ----------
    u : RawUrdf
        The file as ``urdf_source.read_urdf`` read it (its tree is changed in place).
    findings : sequence of Finding
        What ``lint_file`` found; only these are corrected.
    inertia : {"nearest", "geometry"}
        An invalid inertia becomes the nearest valid tensor (principal axes kept, moments moved least),
        or the collision geometry's (solid, uniform) at the link's stated mass; ``"geometry"`` also
        replaces placeholder inertias and inertias the geometry cannot hold.
    density : float
        kg/m^3 giving a moving link without mass the mass of its collision geometry.
    meshes : MeshCache, optional
        Where the meshes are (default: beside ``u.file``).

    Returns
    -------
    (str, list of str)
        The file's text (its own XML declaration, comments and layout kept) and one line per change,
        or per error left as it is ("not fixed (...)").
    """
    from lxml import etree  # type: ignore[import-untyped, unused-ignore]

    if inertia not in ("nearest", "geometry"):
        raise ValueError(f"inertia={inertia!r}: nearest or geometry")
    meshes = meshes or MeshCache(u.file)
    links = {ln.name: ln for ln in u.links}
    joints = {j.name: j for j in u.joints}
    changes: list[str] = []
    done: set[tuple[str, str]] = set()
    for f in findings:
        name = f.element.split("'")[1] if "'" in f.element else ""
        key = (f.code, name)
        if key in done or f.severity == "info":
            continue
        done.add(key)
        where = f"{f.file}:{f.line}: {f.element}"
        if f.code == "limits-reversed" and name in joints:
            lim = joints[name].limit
            lo, hi = lim.get("lower"), lim.get("upper")
            lim.set("lower", hi)
            lim.set("upper", lo)
            changes.append(f"{where}: limits swapped: lower {hi}, upper {lo}")
        elif f.code == "axis-not-unit" and name in joints:
            ax = joints[name].el.find("axis")
            v = np.array([float(x) for x in ax.get("xyz").split()])
            ax.set("xyz", " ".join(_num(x) for x in v / np.linalg.norm(v)))
            changes.append(f"{where}: axis normalised to {ax.get('xyz')}")
        elif f.code in ("mimic-missing", "mimic-cycle") and name in joints and joints[name].mimic is not None:
            mimic = joints[name].mimic
            before = mimic.getprevious()
            if before is not None:  # the layout around it stays: the line goes, nothing else moves
                before.tail = mimic.tail
            joints[name].el.remove(mimic)
            changes.append(f"{where}: <mimic> removed (warning: the joint now moves on its own)")
        elif f.code in _INERTIA_CODES + _GEOMETRY_ONLY and name in links:
            ln = links[name]
            if ln.inertia is None or not ln.mass:
                changes.append(f"{where}: not fixed ({f.code}): the link itself has no mass to give an inertia")
                continue
            if inertia == "geometry":
                solid = link_solid(ln, meshes)
                if solid is None or solid.volume <= 0:
                    changes.append(f"{where}: not fixed ({f.code}): no usable collision geometry for --inertia geometry")
                    continue
                new = solid.inertia * (ln.mass / solid.volume)
                how = f"the collision geometry's at its mass {ln.mass:g} kg"
            elif f.code in _GEOMETRY_ONLY:
                changes.append(f"{where}: not fixed ({f.code}): the inertia is valid; --inertia geometry replaces it")
                continue
            else:
                new = nearest_inertia(ln.inertia, ln.mass)
                how = "the nearest valid tensor"
            _write_inertial(ln, ln.mass, ln.com, new)
            w = principal(new)[0]
            changes.append(f"{where}: inertia replaced by {how} (principal moments "
                           + ", ".join(f"{x:.4g}" for x in w) + " kg m^2)")
        elif f.code == "mass-zero-moving" and name in links:
            ln = links[name]
            solid = link_solid(ln, meshes)
            if solid is None or solid.volume <= 0:
                changes.append(f"{where}: not fixed (no mass): the link has no usable geometry to derive it from")
                continue
            m = density * solid.volume
            _write_inertial(ln, m, solid.centre, density * solid.inertia)
            changes.append(f"{where}: mass {m:.6g} kg, centre and inertia from its geometry at {density:g} kg/m^3")
        elif f.severity == "error" or f.code in ("limits-zero-range", "effort-zero", "velocity-zero"):
            changes.append(f"{where}: not fixed ({f.code}): {f.fix}")
    for c in u.root.itersiblings(preceding=True):  # a comment before <robot>: on its own line, as it was
        c.tail = "\n"
    text = etree.tostring(u.root.getroottree(), encoding="unicode")  # the comments around <robot> too
    return (u.declaration + "\n" if u.declaration else "") + text + "\n", changes
