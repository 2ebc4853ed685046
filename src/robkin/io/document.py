"""The robot document (YAML or JSON): reading, validating, cross-checking and writing.

Schema (docs/conventions.md): ``robkin: 1``, optional ``name``, ``joints`` (one entry per joint: name, type
revolute|prismatic, optional limits {lower, upper} and flip), and at least one representation section:
``gjd``, ``dh``, ``mdh``, ``hayati``, ``rpy_xyz``, ``poe``, ``poe_body``; optionally ``world``, the
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
import math
import os
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from .. import se3
from ..errors import InputError
from ..representations import DHTable, HayatiTable, MDHTable, PoE, RPYTable
from ..representations.gjd import robot_from_gjd
from ..robot import JOINT_TYPES, Joint, Robot, check_pose
from .files import read_text_file
from .numbers import MAX_INT_DIGITS, matrix, number, number_list

__all__ = ["SECTIONS", "ANGLE_UNITS", "AngleUnitWarning", "read_document", "parse_document", "read_sections",
           "document_from_robot", "dump", "same_robot", "read_text", "parse_text", "table_document", "section_key"]

#: Representation sections, in the order that decides which one defines the GJD when several are given.
SECTIONS = ("gjd", "dh", "mdh", "hayati", "rpy_xyz", "poe", "poe_body")
DOC_VERSION = 1
_DH_KEYS = ("a", "d", "alpha", "theta")
_RPY_KEYS = ("roll", "pitch", "yaw", "x", "y", "z")
_HAYATI_KEYS = ("a", "d", "alpha", "theta", "beta")
#: Which columns of each section's rows are angles (converted for ``angles: degrees``).
_ANGLE_COLUMNS = {"dh": ("alpha", "theta"), "mdh": ("alpha", "theta"), "hayati": ("alpha", "theta", "beta"),
                  "rpy_xyz": ("roll", "pitch", "yaw")}
ANGLE_UNITS = ("radians", "degrees")
#: An angle in radians larger than this in magnitude draws a warning: a full turn is the most any
#: table parameter or joint limit needs in practice (UR's limits are exactly +-2 pi, hence the
#: margin of rounding), and 90 or 180 in radians is almost surely a value typed in degrees.
ANGLE_WARN = 2 * math.pi * (1 + 1e-9)
#: Largest input file read (a robot document is a few kB; this stops accidental huge inputs early).
MAX_BYTES = 16 * 1024 * 1024
#: Sections agree if their tool poses agree to this (rotation entries; positions relative to the
#: robot's size) at home and at a few fixed configurations: loose enough for documents written by
#: other tools with 6-7 significant digits, tight enough to catch any real difference of a joint.
AGREE_TOL = 1e-6


class AngleUnitWarning(UserWarning):
    """An angle read in radians is larger than a full turn: it was probably typed in degrees."""


# ---------------------------------------------------------------------------------------- reading
def read_document(path: str | os.PathLike[str]) -> Robot:
    """Read a robot document (.yaml, .yml or .json) into a Robot; InputError names file and field."""
    text, fmt = read_text(path)
    return parse_document(text, fmt, source=str(path))


def read_text(path: str | os.PathLike[str]) -> tuple[str, str]:
    """The text of a document file and its format ('yaml' or 'json'); InputError names the problem."""
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

    from .safe_yaml import load_yaml

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
    """Parse document text (fmt 'yaml' or 'json') into a Robot."""
    data = parse_text(text, fmt, source)
    try:
        sections, joints, name = _sections(data)
        return _robot_from_sections(sections, joints, name, _angle_unit(data))
    except InputError as exc:
        raise exc.in_source(source) from None


def read_sections(path: str | os.PathLike[str]) -> dict[str, Robot]:
    """Each representation section of a document as its own Robot (for comparing them)."""
    text, fmt = read_text(path)
    data = parse_text(text, fmt, str(path))
    try:
        sections, joints, name = _sections(data)
        sections.pop("world", None)
        unit = _angle_unit(data)
        return {key: _robot_of(key, value, joints, name, unit) for key, value in sections.items()}
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


def _angle(value: float, field: str, unit: str) -> float:
    """An angle read in ``unit``, in radians; a warning naming the field for radians beyond 2 pi."""
    if unit == "degrees":
        return math.radians(value)
    if abs(value) > ANGLE_WARN:
        import warnings

        warnings.warn(f"{field}: {value:g} rad is more than a full turn; if it is meant in degrees, add "
                      f"'angles: degrees' to the document", AngleUnitWarning, stacklevel=2)
    return value


def _joints(value: Any, unit: str = "radians") -> tuple[Joint, ...]:
    if value is None:
        raise InputError("joints: missing; list one entry per joint, e.g. {name: joint1, type: revolute}")
    if not isinstance(value, list) or not value:
        raise InputError("joints: expected a non-empty list of {name, type, limits, flip} entries")
    out = []
    for i, entry in enumerate(value):
        where = f"joints[{i}]"
        if isinstance(entry, str):
            entry = {"type": entry}
        if not isinstance(entry, Mapping):
            raise InputError(f"{where}: expected a mapping like {{name: joint{i + 1}, type: revolute}}")
        extra = sorted(str(k) for k in entry if k not in ("name", "type", "limits", "flip"))
        if extra:
            raise InputError(f"{where}: unknown key(s) {', '.join(extra)}; known: name, type, limits, flip")
        name = str(entry.get("name", f"joint{i + 1}"))
        jtype = entry.get("type")
        if jtype is None:
            raise InputError(f"{where} ('{name}').type: missing; one of {', '.join(JOINT_TYPES)}")
        jtype = str(jtype).lower()
        if jtype == "continuous":
            jtype = "revolute"
        if jtype not in JOINT_TYPES:
            raise InputError(f"{where} ('{name}').type: '{entry.get('type')}' is not one of {', '.join(JOINT_TYPES)}")
        flip = entry.get("flip", False)
        if not isinstance(flip, bool):
            raise InputError(f"{where} ('{name}').flip: expected true or false, got {flip!r}")
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
                    v = _angle(v, field, unit)
                if bound == "lower":
                    lower = v
                else:
                    upper = v
        out.append(Joint(name, jtype, lower, upper, flip))  # type: ignore[arg-type]
    return tuple(out)


def _mapping(value: Any, key: str, allowed: tuple[str, ...]) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise InputError(f"{key}: expected a mapping with {', '.join(allowed)}")
    extra = sorted(str(k) for k in value if k not in allowed)
    if extra:
        raise InputError(f"{key}: unknown key(s) {', '.join(extra)}; known: {', '.join(allowed)}")
    return value


def _rows(value: Any, key: str, columns: tuple[str, ...], unit: str = "radians") -> list[list[float]]:
    if not isinstance(value, list) or not value:
        raise InputError(f"{key}: expected a list of rows ({', '.join(columns)})")
    rows = []
    for i, row in enumerate(value):
        where = f"{key}[{i}]"
        if isinstance(row, Mapping):
            missing = [c for c in columns if c not in row]
            extra = sorted(str(k) for k in row if k not in columns)
            if missing or extra:
                raise InputError(f"{where}: expected keys {', '.join(columns)}"
                                 + (f"; missing {', '.join(missing)}" if missing else "")
                                 + (f"; unknown {', '.join(extra)}" if extra else ""))
            rows.append([number(row[c], f"{where}.{c}") for c in columns])
        else:
            rows.append(number_list(row, where, len(columns)))
    section = key.split(".")[0]
    for j, c in enumerate(columns):
        if c in _ANGLE_COLUMNS.get(section, ()):
            for i, row in enumerate(rows):
                row[j] = _angle(row[j], f"{key}[{i}].{c}", unit)
    return rows


def _pose(section: Mapping[str, Any], key: str, prefix: str) -> np.ndarray:
    if section.get(key) is None:
        return np.eye(4)
    return np.array(matrix(section[key], f"{prefix}.{key}"))


def _robot_of(key: str, value: Any, joints: tuple[Joint, ...], name: str | None,
              unit: str = "radians") -> Robot:
    n = len(joints)
    if key == "hayati":
        sec = _mapping(value, key, ("base", "rows", "tool"))
        rows = _rows(sec.get("rows"), "hayati.rows", _HAYATI_KEYS, unit)
        return HayatiTable(np.array(rows), joints, base=_pose(sec, "base", key),
                           tool=_pose(sec, "tool", key)).to_robot(name)
    if key in ("dh", "mdh"):
        sec = _mapping(value, key, ("base", "rows", "tool"))
        rows = _rows(sec.get("rows"), f"{key}.rows", _DH_KEYS, unit)
        base = _pose(sec, "base", key)
        if key == "dh" and len(rows) == n + 1 and sec.get("base") is None:
            base = se3.dh_matrix(*rows[0])  # the paper's layout: row 0 is a fixed base row
            rows = rows[1:]
        cls = DHTable if key == "dh" else MDHTable
        return cls(np.array(rows), joints, base=base, tool=_pose(sec, "tool", key)).to_robot(name)
    if key in ("poe", "poe_body"):
        sec = _mapping(value, key, ("frame", "M", "screws"))
        frame = sec.get("frame", "space" if key == "poe" else "body")
        if frame not in ("space", "body"):
            raise InputError(f"{key}.frame: '{frame}' is not one of space, body")
        if sec.get("M") is None:
            raise InputError(f"{key}.M: missing; the 4x4 home pose of the tool")
        screws = sec.get("screws")
        if not isinstance(screws, list):
            raise InputError(f"{key}.screws: expected a list of [wx, wy, wz, vx, vy, vz], one per joint")
        S = [number_list(s, f"{key}.screws[{i}]", 6) for i, s in enumerate(screws)]
        return PoE(np.array(matrix(sec["M"], f"{key}.M")), np.array(S).reshape(-1, 6), joints,
                   frame).to_robot(name)
    if key == "rpy_xyz":
        sec = _mapping(value, key, ("rows",))
        return RPYTable(np.array(_rows(sec.get("rows"), "rpy_xyz.rows", _RPY_KEYS, unit)), joints).to_robot(name)
    if key == "gjd":
        sec = _mapping(value, key, ("frames",))
        frames = sec.get("frames")
        if not isinstance(frames, list):
            raise InputError(f"gjd.frames: expected a list of n + 1 = {n + 1} 4x4 matrices")
        return robot_from_gjd([matrix(F, f"gjd.frames[{i}]") for i, F in enumerate(frames)], joints, name)
    raise InputError(f"unknown section '{key}'")  # pragma: no cover - keys come from SECTIONS


def _robot_from_sections(sections: dict[str, Any], joints: tuple[Joint, ...], name: str | None,
                         unit: str = "radians") -> Robot:
    world = sections.pop("world", None)
    robots = {key: _robot_of(key, value, joints, name, unit) for key, value in sections.items()}
    keys = list(robots)
    primary = robots[keys[0]]
    for other in keys[1:]:
        diff = same_robot(primary, robots[other])
        if diff is not None:
            raise InputError(f"sections {keys[0]} and {other} describe different robots ({diff}); "
                             f"remove one or make them agree")
    if "rpy_xyz" in robots and keys[0] != "rpy_xyz":
        primary = primary.replace(world=robots["rpy_xyz"].world)
    if world is not None:
        W = check_pose(matrix(world, "world"), "world")
        if "rpy_xyz" in robots and not np.allclose(W, robots["rpy_xyz"].world, atol=AGREE_TOL * primary.scale):
            raise InputError("world and rpy_xyz.rows[0] give different world->base transforms; "
                             "remove one or make them agree")
        primary = primary.replace(world=W)
    return primary


def same_robot(a: Robot, b: Robot, tol: float = AGREE_TOL) -> str | None:
    """None if two robots have the same FK (checked at home and fixed configurations), else why not."""
    if a.n != b.n:
        return f"{a.n} vs {b.n} joints"
    if a.types != b.types:
        return f"joint types {a.types} vs {b.types}"
    rng = np.random.default_rng(20260101)  # fixed: the check is deterministic
    Q = np.vstack([np.zeros(a.n), rng.uniform(-1.0, 1.0, size=(6, a.n))])
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


# ---------------------------------------------------------------------------------------- writing
def _clean(x: float) -> float:
    """A plain float for output: the value itself (written with repr, so it reads back bit-exact),
    with -0.0 written as 0."""
    return float(x) + 0.0


def _mat(T: np.ndarray) -> list[list[float]]:
    return [[_clean(v) for v in row] for row in np.asarray(T)]


def _joint_entry(j: Joint, degrees: bool) -> dict[str, Any]:
    entry: dict[str, Any] = {"name": j.name, "type": j.type}
    if j.lower is not None or j.upper is not None:
        conv = math.degrees if degrees and j.revolute else float
        entry["limits"] = {k: _clean(conv(v)) for k, v in (("lower", j.lower), ("upper", j.upper))
                           if v is not None}
    if j.flip:
        entry["flip"] = True
    return entry


def document_from_robot(robot: Robot, sections: tuple[str, ...] = SECTIONS, *,
                        degrees: bool = False) -> dict[str, Any]:
    """A robot document (dict) with ``joints`` and the requested sections (default: all).

    With ``degrees`` every angle (table angle columns, revolute joint limits) is written in degrees
    and the document says ``angles: degrees``.
    """
    from ..representations import (dh_from_robot, hayati_from_robot, mdh_from_robot, poe_from_robot,
                                   rpy_from_robot)

    doc: dict[str, Any] = {"robkin": DOC_VERSION}
    if robot.name:
        doc["name"] = robot.name
    if degrees:
        doc["angles"] = "degrees"
    doc["joints"] = [_joint_entry(j, degrees) for j in robot.joints]
    if not np.allclose(robot.world, np.eye(4), rtol=0, atol=1e-15):
        doc["world"] = _mat(robot.world)  # world -> robot base: kept, but not part of FK
    tables = {"dh": dh_from_robot, "mdh": mdh_from_robot, "hayati": hayati_from_robot}
    for key in sections:
        if key in tables:
            doc[key] = _section(tables[key](robot), degrees)
        elif key in ("poe", "poe_body"):
            doc[key] = _section(poe_from_robot(robot, "space" if key == "poe" else "body"))
        elif key == "rpy_xyz":
            doc["rpy_xyz"] = _section(rpy_from_robot(robot), degrees)
        elif key == "gjd":
            doc["gjd"] = {"frames": [_mat(F) for F in robot.frames]}
        else:
            raise InputError(f"unknown section '{key}'; one of {', '.join(SECTIONS)}")
    return doc


def section_key(table: Any) -> str:
    """The document section a DHTable, MDHTable, HayatiTable, PoE or RPYTable is written to."""
    from ..representations import PoE, RPYTable

    if isinstance(table, PoE):
        return "poe" if table.frame == "space" else "poe_body"
    return "rpy_xyz" if isinstance(table, RPYTable) else table.SECTION


def _section(table: Any, degrees: bool = False) -> dict[str, Any]:
    """The section of a DHTable, MDHTable, HayatiTable, PoE or RPYTable as a document holds it (angle
    columns in degrees if asked)."""
    key = section_key(table)
    if key in ("dh", "mdh", "hayati"):
        keys = _HAYATI_KEYS if key == "hayati" else _DH_KEYS
        return {"base": _mat(table.base), "rows": _named_rows(table.rows, keys, key, degrees),
                "tool": _mat(table.tool)}
    if key in ("poe", "poe_body"):
        return {"frame": table.frame, "M": _mat(table.M), "screws": _mat(table.screws)}
    return {"rows": _named_rows(table.rows, _RPY_KEYS, key, degrees)}


def table_document(table: Any, degrees: bool = False) -> dict[str, Any]:
    """A robot document (dict) holding one table (DHTable, MDHTable, HayatiTable, PoE or RPYTable) and
    its joints (angles in degrees if asked)."""
    doc: dict[str, Any] = {"robkin": DOC_VERSION}
    if degrees:
        doc["angles"] = "degrees"
    doc["joints"] = [_joint_entry(j, degrees) for j in table.joints]
    doc[section_key(table)] = _section(table, degrees)
    return doc


def _named_rows(rows: np.ndarray, keys: tuple[str, ...], section: str, degrees: bool) -> list[dict[str, float]]:
    angles = _ANGLE_COLUMNS.get(section, ()) if degrees else ()
    return [{k: _clean(math.degrees(v) if k in angles else v) for k, v in zip(keys, row)} for row in rows]


def dump(doc: Mapping[str, Any], fmt: str = "yaml") -> str:
    """Serialise a document as 'yaml' (flow-style rows and matrices) or 'json' (indented)."""
    if fmt == "json":
        from .jsontext import dumps

        return dumps(doc, exact=True) + "\n"
    if fmt != "yaml":
        raise InputError(f"format '{fmt}' is not one of yaml, json")
    import yaml

    class _Dumper(yaml.SafeDumper):  # type: ignore[misc]  # yaml has no type hints here
        pass

    def _repr_float(dumper: yaml.SafeDumper, value: float) -> Any:
        # repr: the shortest string that reads back to the same float (full precision). YAML 1.1
        # resolves "1e-17" as a string, so the mantissa gets a ".0" ("1.0e-17").
        text = repr(value) if math.isfinite(value) else ".nan"
        if "e" in text and "." not in text:
            text = text.replace("e", ".0e")
        return dumper.represent_scalar("tag:yaml.org,2002:float", text)

    _Dumper.add_representer(float, _repr_float)
    return yaml.dump(dict(doc), Dumper=_Dumper, sort_keys=False, default_flow_style=None, width=120)
