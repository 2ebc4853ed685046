"""The robot document (YAML or JSON): reading, validating and cross-checking (writing: ``writer``).

Schema (docs/conventions.md): ``robkin: 1``, optional ``name``, ``joints`` (one entry per joint: name, type
revolute|prismatic, optional limits {lower, upper}, flip and stiffness (N m/rad, or N/m for a
prismatic joint: a compliance calibration's; never converted by ``angles``)), and at least one
representation section: ``gjd``, ``dh``, ``mdh``, ``hayati``, ``rpy_xyz``, ``poe``, ``poe_body``; optionally ``world``, the
world -> robot base transform (4x4; also row 0 of ``rpy_xyz``), kept and written out but not part of
FK, and ``angles``. Rows may be objects with named keys or lists in column order; numbers may be
arithmetic strings such as "-pi/2". A ``dh`` table with n + 1 rows and no ``base`` is the conversion
paper's layout: its first row is the fixed base row.

``angles: degrees`` (default ``radians``) says that every angle in the document is in degrees: the
alpha, theta (and Hayati beta) columns of ``dh``, ``mdh`` and ``hayati`` rows, roll/pitch/yaw of
``rpy_xyz`` rows, and the limits of revolute joints. In radians, such an angle larger than 2 pi in
magnitude draws a warning naming the field (``alpha: 90`` is almost surely meant in degrees).

If a document holds several sections they must describe the same robot; otherwise an InputError names
the sections that disagree.

Floats are written with ``repr``, the shortest text that reads back to the same float, so a document
written and read again gives bit-identical numbers.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ...errors import InputError, quote
from ...representations.registry import by_section
from ...robot import JOINT_TYPES, Joint, Robot, check_pose
from ...samples import unit_sample
from .masses import same_masses
from .sections import AngleUnitWarning, angle, robot_of_section
from .vocabulary import ANGLE_UNITS, DOC_VERSION, SECTIONS
from .writer import document_from_robot, dump, section_key, table_document
from ..files.input_files import read_text_file
from ..files.numbers import MAX_INT_DIGITS, matrix, number
from ...compiled.scanners.vocabulary import MAX_JOINTS

__all__ = ["SECTIONS", "ANGLE_UNITS", "AngleUnitWarning", "read_document", "parse_document", "read_sections",
           "document_from_robot", "dump", "same_robot", "read_text", "parse_text", "table_document", "section_key"]

#: Largest input file read (a robot document is a few kB; this stops accidental huge inputs early).
MAX_BYTES = 16 * 1024 * 1024
#: Sections agree if their tool poses agree to this (rotation entries; positions relative to the
#: robot's size) at home and at a few fixed configurations: loose enough for documents written by
#: other tools with 6-7 significant digits, tight enough to catch any real difference of a joint.
AGREE_TOL = 1e-6


# ---------------------------------------------------------------------------------------- reading
def read_document(path: str | os.PathLike[str]) -> Robot:
    """Read a robot document (.yaml, .yml or .json) into a Robot; InputError names file and field.

    ``path``: the file.
    """
    text, fmt = read_text(path)
    return parse_document(text, fmt, source=str(path))


def read_text(path: str | os.PathLike[str]) -> tuple[str, str]:
    """The text of a document file and its format ('yaml' or 'json'); InputError names the problem.

    ``path``: the file.
    """
    p = Path(path)
    ext = p.suffix.lower()
    fmt = {".yaml": "yaml", ".yml": "yaml", ".json": "json"}.get(ext)
    if fmt is None:
        raise InputError(f"{p}: unknown extension '{ext}'; a robot document is .yaml, .yml or .json")
    return read_text_file(p, MAX_BYTES, "a robot document"), fmt


def parse_text(text: str, fmt: str, source: str) -> Any:
    """Plain data (dicts, lists, numbers) from YAML or JSON text; InputError with line and column.

    Bounded for untrusted text: YAML aliases are limited (``safe_yaml``), integers too long for a
    float become +-inf (refused later with the field's name), and deep nesting is an error.

    ``fmt``: 'yaml' or 'json'; ``source``: the name messages give the text (a file name).
    """
    if fmt == "json":
        try:
            return json.loads(text, parse_constant=lambda c: float("nan"), parse_int=_json_int)
        except json.JSONDecodeError as exc:
            raise InputError(f"not valid JSON (line {exc.lineno}, column {exc.colno}): {exc.msg}",
                             source=source) from None
        except RecursionError:
            raise InputError("JSON nested too deeply", source=source) from None
    import yaml  # lazy: PyYAML import is ~20 ms

    from ..files.safe_yaml import load_yaml

    try:
        return load_yaml(text)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark
        where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark else ""
        raise InputError(f"not valid YAML{where}: {exc.problem or exc}", source=source) from None
    except yaml.YAMLError as exc:
        raise InputError(f"not valid YAML: {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}",
                         source=source) from None


def _json_int(text: str) -> int | float:
    """A JSON integer; longer than a float can hold (and than Python converts): +-inf, refused later."""
    if len(text) > MAX_INT_DIGITS:
        return float("-inf") if text.startswith("-") else float("inf")
    return int(text)


def parse_document(text: str, fmt: str = "yaml", source: str = "<document>") -> Robot:
    """Parse document text (fmt 'yaml' or 'json') into a Robot.

    ``text``: the document; ``source``: the name messages give it (a file name).
    """
    data = parse_text(text, fmt, source)
    try:
        sections, joints, name = _sections(data)
        return _robot_from_sections(sections, joints, name, _angle_unit(data))
    except InputError as exc:
        raise exc.in_source(source) from None


def read_sections(path: str | os.PathLike[str]) -> dict[str, Robot]:
    """Each representation section of a document as its own Robot (for comparing them).

    ``path``: the document file.
    """
    text, fmt = read_text(path)
    data = parse_text(text, fmt, str(path))
    try:
        sections, joints, name = _sections(data)
        sections.pop("world", None)
        unit = _angle_unit(data)
        return {key: robot_of_section(key, value, joints, name, unit) for key, value in sections.items()}
    except InputError as exc:
        raise exc.in_source(str(path)) from None


def _sections(data: Any) -> tuple[dict[str, Any], tuple[Joint, ...], str | None]:
    if data is None:
        raise InputError("document is empty; it needs 'joints' and a representation section "
                         f"({', '.join(SECTIONS)})")
    if not isinstance(data, Mapping):
        raise InputError(f"document must be a mapping with 'joints' and a representation section, "
                         f"got {type(data).__name__}")
    version = data.get("robkin", DOC_VERSION)
    if version != DOC_VERSION:
        raise InputError(f"robkin: document version {version!r} is not supported (this is version {DOC_VERSION})")
    known = set(SECTIONS) | {"robkin", "name", "joints", "metrics", "world", "angles"}
    unknown = sorted(str(k) for k in data if k not in known)
    if unknown:
        raise InputError(f"unknown key(s) {', '.join(unknown)}; known: {', '.join(sorted(known))}")
    name = data.get("name")
    if name is not None and not isinstance(name, (str, int, float)):
        raise InputError("name: expected a string")
    joints = _joints(data.get("joints"), _angle_unit(data))
    sections = {k: data[k] for k in SECTIONS if k in data and data[k] is not None}
    if not sections:
        raise InputError(f"no representation section; give at least one of {', '.join(SECTIONS)}")
    if data.get("world") is not None:
        sections["world"] = data["world"]
    return sections, joints, None if name is None else str(name)


def _angle_unit(data: Mapping[str, Any]) -> str:
    """The document's ``angles`` key: 'radians' (default) or 'degrees'; InputError otherwise."""
    unit = data.get("angles", "radians")
    if unit not in ANGLE_UNITS:
        raise InputError(f"angles: {unit!r} is not one of {', '.join(ANGLE_UNITS)}")
    return str(unit)


def _joints(value: Any, unit: str = "radians") -> tuple[Joint, ...]:
    if value is None:
        raise InputError("joints: missing; list one entry per joint, e.g. {name: joint1, type: revolute}")
    if not isinstance(value, list) or not value:
        raise InputError("joints: expected a non-empty list of {name, type, limits, flip} entries")
    if len(value) > MAX_JOINTS:
        raise InputError(f"joints: {len(value)} entries; at most {MAX_JOINTS} joints are read")
    out = []
    for i, entry in enumerate(value):
        where = f"joints[{i}]"
        if isinstance(entry, str):
            entry = {"type": entry}
        if not isinstance(entry, Mapping):
            raise InputError(f"{where}: expected a mapping like {{name: joint{i + 1}, type: revolute}}")
        extra = sorted(str(k) for k in entry if k not in ("name", "type", "limits", "flip", "stiffness"))
        if extra:
            raise InputError(f"{where}: unknown key(s) {', '.join(extra)}; known: name, type, limits, flip, stiffness")
        name = str(entry.get("name", f"joint{i + 1}"))
        jtype = entry.get("type")
        if jtype is None:
            raise InputError(f"{where} ('{name}').type: missing; one of {', '.join(JOINT_TYPES)}")
        jtype = str(jtype).lower()
        if jtype == "continuous":
            jtype = "revolute"
        if jtype not in JOINT_TYPES:
            raise InputError(f"{where} ('{name}').type: {quote(entry.get('type'))} is not one of {', '.join(JOINT_TYPES)}")
        flip = entry.get("flip", False)
        if not isinstance(flip, bool):
            raise InputError(f"{where} ('{name}').flip: expected true or false, got {quote(flip)}")
        lower = upper = None
        limits = entry.get("limits")
        if limits is not None:
            if not isinstance(limits, Mapping):
                raise InputError(f"{where} ('{name}').limits: expected {{lower: ..., upper: ...}}")
            bad = sorted(str(k) for k in limits if k not in ("lower", "upper"))
            if bad:
                raise InputError(f"{where} ('{name}').limits: unknown key(s) {', '.join(bad)}; known: lower, upper")
            for bound in ("lower", "upper"):
                if limits.get(bound) is None:
                    continue
                field = f"{where} ('{name}').limits.{bound}"
                v = number(limits[bound], field)
                if jtype == "revolute":
                    v = angle(v, field, unit)
                if bound == "lower":
                    lower = v
                else:
                    upper = v
        stiffness = None
        if entry.get("stiffness") is not None:  # N m/rad (N/m prismatic): never an angle, so never converted
            field = f"{where} ('{name}').stiffness"
            stiffness = number(entry["stiffness"], field)
            if not stiffness > 0:
                raise InputError(f"{field}: {stiffness} is not a positive number (N m/rad, or N/m for a prismatic "
                                 f"joint)")
        out.append(Joint(name, jtype, lower, upper, flip, stiffness=stiffness))  # type: ignore[arg-type]
    return tuple(out)


def _robot_from_sections(sections: dict[str, Any], joints: tuple[Joint, ...], name: str | None,
                         unit: str = "radians") -> Robot:
    world = sections.pop("world", None)
    robots = {key: robot_of_section(key, value, joints, name, unit) for key, value in sections.items()}
    keys = list(robots)
    primary = robots[keys[0]]
    for other in keys[1:]:
        diff = same_robot(primary, robots[other])
        if diff is not None:
            raise InputError(f"sections {keys[0]} and {other} describe different robots ({diff}); "
                             f"remove one or make them agree")
    primary = _with_masses(primary, robots)
    # a section whose first row is world -> base (RPY-XYZ) gives the world transform too
    worlds = [k for k in keys if by_section(k).layout == "rpy"]
    if worlds and keys[0] != worlds[0]:
        primary = primary.replace(world=robots[worlds[0]].world)
    if world is not None:
        W = check_pose(matrix(world, "world"), "world")
        if worlds and not np.allclose(W, robots[worlds[0]].world, atol=AGREE_TOL * primary.scale):
            raise InputError(f"world and {worlds[0]}.rows[0] give different world->base transforms; "
                             "remove one or make them agree")
        primary = primary.replace(world=W)
    return primary


def _with_masses(primary: Robot, robots: dict[str, Robot]) -> Robot:
    """The primary section's robot with the mass properties of the first section that gives them;
    every other section that gives them must agree (else an InputError names both)."""
    keys = [k for k, r in robots.items() if r.bodies.inertials]
    if not keys:
        return primary
    for other in keys[1:]:
        diff = same_masses(robots[keys[0]], robots[other], AGREE_TOL)
        if diff is not None:
            raise InputError(f"sections {keys[0]} and {other} give different mass properties ({diff}); "
                             f"remove the mass fields of one or make them agree")
    return primary if robots[keys[0]] is primary else primary.replace(bodies=robots[keys[0]].bodies)


def same_robot(a: Robot, b: Robot, tol: float = AGREE_TOL) -> str | None:
    """None if two robots have the same FK (checked at home and fixed configurations), else why not.

    ``a``, ``b``: the robots; ``tol``: the largest FK difference allowed (the robot's length unit, radians).
    """
    if a.n != b.n:
        return f"{a.n} vs {b.n} joints"
    if a.types != b.types:
        return f"joint types {a.types} vs {b.types}"
    Q = np.vstack([np.zeros(a.n), 2.0 * unit_sample(6, a.n) - 1.0])  # fixed: the check is deterministic
    Ta, Tb = a.fk(Q), b.fk(Q)
    scale = max(a.scale, b.scale)
    rot = np.abs(Ta[:, :3, :3] - Tb[:, :3, :3]).max(axis=(1, 2))
    pos = np.linalg.norm(Ta[:, :3, 3] - Tb[:, :3, 3], axis=1) / scale
    bad = np.nonzero((rot > tol) | (pos > tol))[0]
    if bad.size == 0:
        return None
    k = int(bad[0])
    where = "at q = 0" if k == 0 else f"at q = [{', '.join(f'{v:.3g}' for v in Q[k])}]"
    return f"tool poses differ {where}: position by {pos[k] * scale:.3g}, rotation by {rot[k]:.3g}"


def robot_from_data(data: Any, source: str = "<document>") -> Robot:
    """A Robot from a robot document already parsed into plain data (dicts, lists, numbers), with
    the same checks and messages as a document file; InputError names ``source``."""
    try:
        sections, joints, name = _sections(data)
        return _robot_from_sections(sections, joints, name, _angle_unit(data))
    except InputError as exc:
        raise exc.in_source(source) from None
