"""Parsing a URDF file into its tree (``trees.model.UrdfModel``): one compiled pass of expat
(``compiled.scanners.urdf_scan``) reads links and joints without building an XML tree; the contents of links
(visuals, collisions, inertials) are parsed from the text only when asked for (``content``). A .xacro
file is expanded only on request (``allow_xacro=True``).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from ..files.input_files import read_text_file
from ..trees.model import UrdfJoint, UrdfModel
from ..trees.xml_parse import _extras, _parse_urdf_xml, _refuse_dtd
from ...bodies import LazyTuple
from ...errors import InputError

__all__ = ["parse_urdf", "parse_urdf_text"]

#: Largest URDF read. Vendor URDFs of whole humanoids are ~1 MB; this stops accidental huge inputs.
MAX_BYTES = 64 * 1024 * 1024
#: A joint axis whose norm differs from 1 by more than this is normalised with a warning; below it
#: the difference is decimal rounding of a typed unit vector (e.g. 0.707107) and is fixed silently.
AXIS_UNIT_TOL = 1e-6
#: A joint axis shorter than this is no direction at all (URDF axes are unit vectors, typed with a
#: few decimals; anything this short is a zero or a typo).
AXIS_ZERO_TOL = 1e-9
#: The one-line refusal of a .xacro file read without the opt-in (why, and the two ways out).
XACRO_REFUSED = ("{path}: not expanded: a .xacro file is a program (it can run code, read files and environment "
                 "variables); if you trust it, pass allow_xacro=True or expand it "
                 "yourself: xacro {path} > {stem}.urdf")


# ------------------------------------------------------------------------------------------ reading
def _read_source(source: str | os.PathLike[str], allow_xacro: bool = False) -> tuple[str, str]:
    """(XML text, name of the source for messages) from a path or an XML string."""
    if isinstance(source, str) and source.lstrip().startswith("<"):
        return source, "<urdf string>"
    name = os.fspath(source)  # no Path for a plain file: making one costs ~10 us of a small URDF's load
    if os.path.splitext(name)[1].lower() == ".xacro":
        p = Path(name)
        if not allow_xacro:
            raise InputError(XACRO_REFUSED.format(path=p, stem=p.stem))
        return _expand_xacro(p), str(p)
    text = read_text_file(name, MAX_BYTES, "a URDF")
    if not text or text.isspace():
        raise InputError(f"{name}: file is empty; expected a URDF <robot> element")
    return text, name


def _expand_xacro(path: Path) -> str:
    """A .xacro file expanded to URDF text with the optional ``xacro`` package."""
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    try:
        import xacro  # lazy, optional: pip install 'robkin[xacro]'
    except ImportError:
        raise InputError(f"{path}: .xacro input needs the 'xacro' package (pip install 'robkin[xacro]'); "
                         f"or expand it first: xacro {path.name} > robot.urdf") from None
    try:
        doc = xacro.process_file(str(path))
        return doc.toxml()
    except Exception as exc:  # xacro raises many types (XacroException, XML errors, NameError...)
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(f"{path}: xacro expansion failed: {msg}") from None


def _mimic(joint: str, multiplier: float, offset: float) -> Any:
    """A ``body_parts.Mimic``, its module imported only for a file with a <mimic> (each frozen dataclass
    costs start-up to define; most URDFs have none)."""
    from ...body_parts import Mimic

    return Mimic(joint, multiplier, offset)


def parse_urdf(source: str | os.PathLike[str], *, allow_xacro: bool = False) -> UrdfModel:
    """Parse and validate the kinematic tree of a URDF (path, .xacro path, or XML string).

    A .xacro path is expanded only with ``allow_xacro=True``: xacro evaluates Python expressions and
    reads files and environment variables named in the file, so only trusted files may be expanded.

    Checks: a <robot> root; unique link and joint names; every joint's parent and child link exist;
    each link has at most one parent joint; one root link; no cycles. Messages name file, joint, link.
    """
    text, src = _read_source(source, allow_xacro)
    return parse_urdf_text(text, src)


def parse_urdf_text(text: str, src: str = "<urdf string>") -> UrdfModel:
    """``parse_urdf`` of URDF text; ``src`` names it in messages."""
    from ...compiled.scanners.urdf_scan import scan_urdf  # compiled: loaded by a read, not by an import
    from .content import LazyLinkContent

    _refuse_dtd(text, src)
    name, links, joints = scan_urdf(text, src, UrdfJoint, _mimic)
    # the tree is built only if link contents or the extras are asked for, once for both
    tree: list[Any] = []

    def root() -> Any:  # a plain memo: functools.cache builds a wrapper per call (~3 us of a small file's load)
        if not tree:
            tree.append(_parse_urdf_xml(text, src))
        return tree[0]

    return UrdfModel(name, links, joints, src, LazyLinkContent(links, root, src), LazyTuple(lambda: _extras(root())))
