"""``robkin lint --fix`` of an MJCF file: changed only where lint reported something it can correct, one line
per change; the file's comments, layout, defaults and includes stay as they are.

What is fixed (the same choices as ``fix_urdf``, one implementation of each tensor: ``nearest_inertia``):
a reversed ``range`` (swapped), an ``axis`` not of unit length (normalised), an ``<inertial>`` that is not
positive definite, breaks the triangle inequality or is singular (the nearest valid tensor, or the
collision geometry's at the body's mass), placeholder inertias and inertias the geometry cannot hold
(``inertia="geometry"`` only), and a moving body without mass (an ``<inertial>`` of its collision
geometry at ``density``). A new ``<inertial>`` is written as ``pos`` + ``fullinertia`` in the body frame.
Elements of included files and masses MuJoCo takes from geoms are left as they are and said ("not
fixed: ..."). The ``<compiler>`` settings are left: the fixed file needs no ``balanceinertia`` or
``boundmass``, and lint keeps saying that MuJoCo changes what they change.
"""

from __future__ import annotations

from typing import Any, Iterator, Sequence

import numpy as np

from .findings import Finding
from .fix_urdf import _GEOMETRY_ONLY, _INERTIA_CODES, nearest_inertia
from .geometry import MeshCache, link_solid
from .mass_checks import principal
from .urdf_source import RawUrdf

__all__ = ["fix_mjcf", "parse_keeping_comments"]


def _num(x: float) -> str:
    from ..io.files.float_text import float_text

    return float_text(float(x))


def _write_inertial(body: Any, mass: float, com: np.ndarray, I: np.ndarray) -> None:
    """Replace (or add, first in the body) the body's ``<inertial>``: pos, mass, fullinertia in the body frame."""
    from lxml import etree  # type: ignore[import-untyped, unused-ignore]

    from .model_source import _find

    old = _find(body, "inertial")
    new = etree.Element("inertial")
    new.set("pos", " ".join(_num(v) for v in com))
    new.set("mass", _num(mass))
    # MJCF's order: ixx iyy izz ixy ixz iyz
    new.set("fullinertia", " ".join(_num(I[r, c]) for r, c in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))))
    if old is not None:
        new.tail = old.tail
        old.getparent().replace(old, new)
    else:
        kids = [c for c in body if isinstance(c.tag, str)]
        new.tail = body.text if body.text and not body.text.strip() else "\n"
        body.insert(0, new) if not kids else kids[0].addprevious(new)


def fixable(findings: Sequence[Finding]) -> Iterator[tuple[Finding, str, str]]:
    """The findings a fix acts on, each (code, element) once and no info: (finding, the element's name,
    'file:line: element' for the change's line). MJCF's and SDF's fixes share it."""
    done: set[tuple[str, str]] = set()
    for f in findings:
        name = f.element.split("'")[1] if "'" in f.element else ""
        if (f.code, name) in done or f.severity == "info":
            continue
        done.add((f.code, name))
        yield f, name, (f"{f.file}:{f.line}: {f.element}" if f.element else f"{f.file}:{f.line}")


def fix_mjcf(path: str, findings: Sequence[Finding], *, inertia: str = "nearest", density: float = 1000.0,
             raw: RawUrdf | None = None, meshes: MeshCache | None = None) -> tuple[str, list[str]]:
    """The corrected MJCF text for the ``findings`` lint gave on ``path``, and one line per change.

    Parameters
    ----------
    path : str
        The MJCF file (read again here, comments kept).
    findings : sequence of Finding
        What ``lint_file`` found; only these are corrected.
    inertia : {"nearest", "geometry"}
        As ``fix_urdf``.
    density : float
        kg/m^3 giving a moving body without mass the mass of its collision geometry.
    raw : RawUrdf, optional
        The file's tree as lint read it (``model_source.raw_from_model``); None when the reader refused
        the file (then only ``range`` and ``axis`` are fixed).
    meshes : MeshCache, optional
        Where the meshes are (default: beside ``path``).

    Returns
    -------
    (str, list of str)
    """
    from .xml_lines import mjcf_lines

    if inertia not in ("nearest", "geometry"):
        raise ValueError(f"inertia={inertia!r}: nearest or geometry")
    text, root = parse_keeping_comments(path)
    lines = mjcf_lines(root)
    links = {ln.name: ln for ln in raw.links} if raw is not None else {}
    meshes = meshes or MeshCache(path)
    changes: list[str] = []
    for f, name, where in fixable(findings):
        joint = lines.joints.get(name) if f.element.startswith("joint") else None
        body = lines.links.get(name) if f.element.startswith("body") else None
        if f.code == "limits-reversed" and joint is not None and joint.get("range"):
            lo, hi = joint.get("range").split()
            joint.set("range", f"{hi} {lo}")
            changes.append(f"{where}: range swapped: {hi} {lo}")
        elif f.code == "axis-not-unit" and joint is not None and joint.get("axis"):
            v = np.array([float(x) for x in joint.get("axis").split()])
            joint.set("axis", " ".join(_num(x) for x in v / np.linalg.norm(v)))
            changes.append(f"{where}: axis normalised to {joint.get('axis')}")
        elif f.code in _INERTIA_CODES + _GEOMETRY_ONLY + ("mass-zero-moving",) and name in links and body is not None:
            changes.append(_fix_mass(f, where, links[name], body, inertia, density, meshes))
        elif f.severity == "error" or f.code in ("limits-zero-range", "effort-zero", "velocity-zero"):
            why = "in an included file" if f.element and joint is None and body is None else f.fix
            changes.append(f"{where}: not fixed ({f.code}): {why}")
    return written(text, root), changes


def parse_keeping_comments(path: str) -> tuple[str, Any]:
    """(text, lxml root) of an XML file, comments kept (``--fix`` writes the tree back)."""
    from lxml import etree  # type: ignore[import-untyped, unused-ignore]

    from ..io.files.input_files import read_text_file

    text = read_text_file(path, 64 * 1024 * 1024, "a robot file")
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False,
                             remove_comments=False, remove_pis=False, encoding="utf-8")
    return text, etree.fromstring(text.encode("utf-8", "surrogatepass"), parser)


def written(text: str, root: Any) -> str:
    """The tree as text, with the input's own XML declaration."""
    from lxml import etree  # type: ignore[import-untyped, unused-ignore]

    head = text.lstrip("\ufeff")
    declaration = head[:head.index("?>") + 2] if head.startswith("<?xml") and "?>" in head[:200] else ""
    out = etree.tostring(root.getroottree(), encoding="unicode")
    return (declaration + "\n" if declaration else "") + out + "\n"


def _fix_mass(f: Finding, where: str, ln: Any, body: Any, inertia: str, density: float, meshes: MeshCache,
              write=None) -> str:
    """Correct one body's mass properties in place (``write(body, mass, com, I)``: an MJCF ``<inertial>`` by
    default); the line saying what was done."""
    write = write or _write_inertial
    if f.code in ("mass-zero-moving", "mass-default"):
        solid = link_solid(ln, meshes)
        if solid is None or solid.volume <= 0:
            return f"{where}: not fixed (no mass): the body has no usable geometry to derive it from"
        m = density * solid.volume
        write(body, m, solid.centre, density * solid.inertia)
        return f"{where}: <inertial> mass {m:.6g} kg, centre and inertia from its geometry at {density:g} kg/m^3"
    if ln.inertia is None or not ln.mass:
        return f"{where}: not fixed ({f.code}): the body has no mass to give an inertia"
    if ln.mass_from == "geoms":
        return f"{where}: not fixed ({f.code}): MuJoCo takes this body's mass from its geoms; give it an <inertial>"
    if inertia == "geometry":
        solid = link_solid(ln, meshes)
        if solid is None or solid.volume <= 0:
            return f"{where}: not fixed ({f.code}): no usable collision geometry for --inertia geometry"
        new, how = solid.inertia * (ln.mass / solid.volume), f"the collision geometry's at its mass {ln.mass:g} kg"
    elif f.code in _GEOMETRY_ONLY:
        return f"{where}: not fixed ({f.code}): the inertia is valid; --inertia geometry replaces it"
    else:
        new, how = nearest_inertia(ln.inertia, ln.mass), "the nearest valid tensor"
    write(body, ln.mass, ln.com, new)
    return (f"{where}: inertia replaced by {how} (principal moments "
            + ", ".join(f"{x:.4g}" for x in principal(new)[0]) + " kg m^2)")
