"""Lint of the formats other than URDF: MJCF and SDF (their trees, with element lines), robot documents and
tables (the robot they hold), USD (its reader's checks).

Every format gets the same checks as URDF, one implementation each (``structure``, ``joint_checks``,
``mass_checks``, ``asset_checks``): MJCF and SDF through the tree their reader builds
(``model_source.raw_from_model``: links, joints, mass properties as MuJoCo compiles them, shapes, each
with its element's source line), documents and tables through the URDF robkin writes of them (each
finding's line is then that of the element's name in the document). A reader's refusal is a finding
(error, with the line of the element it names and, for the usual ones, the check's code and fix), its
warnings (a near-valid value projected) are warnings; a file that is not there, too big or not
parseable at all stays an ``InputError``. MJCF files also get MuJoCo's own verdict (``mjcf_readiness``).
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path
from typing import Mapping

from ..errors import InputError
from .findings import ERROR, INFO, WARNING, Finding

__all__ = ["lint_other", "refusal", "read_tree", "TREE_FORMATS"]

#: reader messages that mean "cannot be read at all" (exit 2), not "read, and wrong" (a finding)
_UNREADABLE = re.compile(r"no such file|not a regular file|larger than|not well-formed|not valid XML|is empty|"
                         r"refused XML|cannot be read|not a file|unknown (?:file )?(?:type|format|extension)|"
                         r"permission|root element is", re.I)
_LINE = re.compile(r"\bline (\d+)")
#: the element a reader's message starts with: "joint 'j1' (body 'b1'): ..."
_ELEMENT = re.compile(r"^(joint|link|body|site|geom|model|mesh) '([^']{1,200})'")
#: the usual refusals as the shared checks' codes and fixes: (pattern, code, fix)
_KNOWN = (
    (re.compile(r"lower end must be below|lower \S+ > upper"), "limits-reversed",
     "swap the two ends (MJCF range=\"LO HI\", SDF <lower> and <upper>)"),
    (re.compile(r"both called '([^']+)'|defined twice|duplicate"), "link-duplicate", "rename one of the two"),
    (re.compile(r"(?:parent|child) '[^']*' is not a link"), "joint-dangling", "name a link of the model"),
    (re.compile(r"axis.*(?:zero|no direction|length)", re.I), "axis-zero", "give the axis its direction"),
)
TREE_FORMATS = {".xml": "mjcf", ".mjcf": "mjcf", ".sdf": "sdf"}


def _line_of_name(path: str, name: str, last: bool = False) -> int | None:
    """The first (``last``: the last) line of a text file naming ``name`` (name="NAME", "NAME" or NAME:)."""
    found = None
    pats = (f'name="{name}"', f"name='{name}'", f'"{name}"', f"name: {name}", f"'{name}'")
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            for k, text in enumerate(fh, 1):
                if any(p in text for p in pats):
                    if not last:
                        return k
                    found = k
    except OSError:
        return None
    return found


def refusal(path: str, msg: str, lines=None) -> Finding:
    """A reader's refusal as a finding: its element, line (the element's), and the check it is."""
    text = msg[len(path) + 2:] if msg.startswith(path + ": ") else msg
    e = _ELEMENT.match(text)
    m = _LINE.search(text)
    code, fix = "reader-refuses", "correct what the message names"
    dup = None
    for pat, c, f in _KNOWN:
        hit = pat.search(text)
        if hit:
            code, fix = c, f
            dup = hit.group(1) if c == "link-duplicate" and hit.groups() else None
            break
    line = int(m.group(1)) if m else None
    if line is None and e is not None:
        el = (lines.joints if e.group(1) == "joint" else lines.links).get(e.group(2)) if lines is not None else None
        line = getattr(el, "sourceline", None) or _line_of_name(path, e.group(2))
    if line is None and dup:
        line = _line_of_name(path, dup, last=True)   # the second of the two is the defect
    element = f"{e.group(1)} '{e.group(2)}'" if e else (f"body '{dup}'" if dup else "")
    return Finding(ERROR, code, path, line, element, text[e.end():].lstrip(" :") if e else text, fix)


_NAMED = re.compile(r"\b(joint|link|body) '([^']{1,200})'")


def _reader_warnings(path: str, caught, lines=None) -> list[Finding]:
    """What a reader changed silently but for a warning, each at the line of the element it names."""
    out = []
    for w in caught:
        if not issubclass(w.category, UserWarning):
            continue
        text = str(w.message).splitlines()[0]
        m = _NAMED.search(text)
        line = None
        if m:
            el = (lines.joints if m.group(1) == "joint" else lines.links).get(m.group(2)) if lines else None
            line = getattr(el, "sourceline", None) or _line_of_name(path, m.group(2))
        out.append(Finding(WARNING, "reader-changes", path, line, f"{m.group(1)} '{m.group(2)}'" if m else "",
                           text, "write the value the reader used (the message names it)"))
    return out


def lint_other(path: str, allow_xacro: bool = False, package_paths: Mapping[str, Path] | None = None,
               max_faces: int | None = None) -> list[Finding]:
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{path}: no such file")
    fmt = TREE_FORMATS.get(p.suffix.lower())
    if fmt is not None:
        return _lint_tree(path, fmt, package_paths, max_faces)
    from ..io import load

    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            robot = load(path, allow_xacro=allow_xacro)
    except InputError as exc:
        if _UNREADABLE.search(str(exc)):
            raise
        return [refusal(path, str(exc))]
    found = _reader_warnings(path, caught)
    if p.suffix.lower() in (".usd", ".usda", ".usdc"):
        return found + _limits(path, robot)
    return found + _lint_robot(path, robot, package_paths, max_faces)


def _limits(path: str, robot) -> list[Finding]:
    return [Finding(ERROR, "limits-reversed", path, _line_of_name(path, j.name), f"joint '{j.name}'",
                    f"lower {j.lower:g} > upper {j.upper:g}", "swap them") for j in robot.joints
            if j.lower is not None and j.upper is not None and j.lower > j.upper]


def _lint_tree(path: str, fmt: str, package_paths, max_faces) -> list[Finding]:
    from .checks import lint_urdf
    from .xml_lines import mjcf_lines, parse_lines, sdf_lines

    root = parse_lines(path)
    lines = (mjcf_lines if fmt == "mjcf" else sdf_lines)(root)
    ready: list[Finding] = []
    if fmt == "mjcf":
        from .mjcf_readiness import mjcf_readiness

        ready = mjcf_readiness(path, lines)
    try:
        raw, refused, caught = _read_tree(path, fmt, lines)
    except InputError as exc:
        if _UNREADABLE.search(str(exc)):
            raise
        return _merge([refusal(path, str(exc), lines)], ready)
    found = _reader_warnings(path, caught, lines) + [refusal(path, m, lines) for m in refused]
    found += lint_urdf(raw, package_paths, max_faces)
    return _merge(found, ready)


def _read_tree(path: str, fmt: str, lines):
    """(RawUrdf, the reader's refusals of the link contents, its warnings) of an MJCF or SDF file."""
    from .model_source import raw_from_model

    if fmt == "mjcf":
        from ..io.mjcf.reader import model_from_mjcf as read
    else:
        from ..io.sdf.reader import model_from_sdf as read
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model, _ = read(path)
        raw, refused = raw_from_model(model, path, fmt, lines)
    return raw, refused, caught


def read_tree(path: str):
    """The ``RawUrdf`` of an MJCF or SDF file as lint checks it, or None when its reader refuses it."""
    from .xml_lines import mjcf_lines, parse_lines, sdf_lines

    fmt = TREE_FORMATS[Path(path).suffix.lower()]
    try:
        return _read_tree(path, fmt, (mjcf_lines if fmt == "mjcf" else sdf_lines)(parse_lines(path)))[0]
    except InputError:
        return None


_MJ_ELEMENT = re.compile(r"Element name '([^']+)'")


def _merge(found: list[Finding], ready: list[Finding]) -> list[Finding]:
    """lint's findings and MuJoCo's verdict (sorted by line), that verdict left out where an error of lint's
    names the same line or element: it is then the same defect, said once, with lint's fix."""
    errors = [f for f in found if f.severity == ERROR]
    said_lines = {f.line for f in errors}
    said_names = {f.element.split("'")[1] for f in errors if "'" in f.element}

    def new(r: Finding) -> bool:
        if r.code != "mujoco-refuses":
            return True
        m = _MJ_ELEMENT.search(r.message)
        return r.line not in said_lines and not (m and m.group(1) in said_names) and not (r.line is None and errors)

    out = found + [r for r in ready if new(r)]
    return sorted(out, key=lambda x: (x.line or 0, ("error", "warning", "info").index(x.severity)))


def _lint_robot(path: str, robot, package_paths, max_faces) -> list[Finding]:
    """A document's or table's robot, through the URDF robkin writes of it; lines are its names' in the file."""
    from dataclasses import replace

    from ..io.urdf.writer import urdf_from_robot
    from .checks import lint_urdf
    from .urdf_source import parse_urdf_text

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # the writer's own notes are about the URDF, not the document
        raw = parse_urdf_text(urdf_from_robot(robot), path)
    raw.fmt = "document"
    # what the document does not say is not wrong: the URDF writer's placeholders for it are left out
    # (effort and velocity 0 where the document gives none; no mass properties at all: kinematics only)
    unsaid = {(f"{k}-zero", f"joint '{j.name}'") for j in robot.joints for k in ("effort", "velocity")
              if getattr(j, k) is None}
    kinematic = not robot.bodies.inertials
    # a link is named in the document by the joint that moves it (its mass sits on that joint's row)
    by_child = {j.child: j.name for j in raw.joints}
    out = []
    for f in lint_urdf(raw, package_paths, max_faces, mesh_base=path):
        if (f.code, f.element) in unsaid or (kinematic and f.code.startswith(("mass-", "inertia-"))):
            continue
        name = f.element.split("'")[1] if "'" in f.element else ""
        line = _line_of_name(path, name) if name else None
        if line is None and name in by_child:
            line = _line_of_name(path, by_child[name])
        out.append(replace(f, line=line))
    if kinematic:
        out.append(Finding(INFO, "no-mass-properties", path, None, "", "the robot has no mass properties: "
                           "kinematics only (dynamics, simulator export and the mass checks need them)",
                           "add the links' inertials (robkin convert from a URDF or MJCF that has them)"))
    return out
