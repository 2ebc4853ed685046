"""Writing robot documents: a Robot or one table as a document (dict), and its YAML/JSON text.

Floats are written with ``repr``, the shortest text that reads back to the same float, so a document
written and read again gives bit-identical numbers. ``robkin.io.documents.reader`` re-exports every name here.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from ...errors import InputError
from ...robot import Joint, Robot
from ...representations.registry import Representation, by_section, of_table
from .vocabulary import ANGLE_COLUMNS, DOC_VERSION, SECTIONS
from .masses import mass_fields

if TYPE_CHECKING:  # pragma: no cover
    from ...representations.mass_rows import MassRows

__all__ = ["document_from_robot", "dump", "section_key", "table_document"]


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
    if j.stiffness is not None:
        entry["stiffness"] = _clean(j.stiffness)
    return entry


def document_from_robot(robot: Robot, sections: Sequence[str] = SECTIONS, *,
                        degrees: bool = False) -> dict[str, Any]:
    """A robot document (dict) with ``joints`` and the requested sections (default: every registered
    one, in document order).

    With ``degrees`` every angle (table angle columns, revolute joint limits) is written in degrees
    and the document says ``angles: degrees``.
    """
    doc: dict[str, Any] = {"robkin": DOC_VERSION}
    if robot.name:
        doc["name"] = robot.name
    if degrees:
        doc["angles"] = "degrees"
    doc["joints"] = [_joint_entry(j, degrees) for j in robot.joints]
    if not np.allclose(robot.world, np.eye(4), rtol=0, atol=1e-15):
        doc["world"] = _mat(robot.world)  # world -> robot base: kept, but not part of FK
    for key in sections:
        try:
            rep = by_section(key)
        except KeyError:
            raise InputError(f"unknown section '{key}'; one of {', '.join(SECTIONS)}") from None
        if rep.layout == "frames":
            doc[key] = {"frames": [_mat(F) for F in rep.table_of(robot)]}
        else:
            doc[key] = _section(rep.table_of(robot), degrees, rep)
    return doc


def section_key(table: Any) -> str:
    """The document section a table (DHTable, MDHTable, HayatiTable, PoE, RPYTable or any registered
    one) is written to."""
    try:
        return of_table(table).section
    except TypeError:
        return table.SECTION  # a bare LinkTable


def _section(table: Any, degrees: bool = False, rep: Representation | None = None) -> dict[str, Any]:
    """The section of a table as a document holds it (angle columns in degrees if asked), laid out
    by its representation's layout (``robkin.representations.registry``)."""
    key = section_key(table)
    rep = rep or by_section(key)
    masses = table.masses
    out: dict[str, Any]
    if rep.layout == "link-table":
        out = {"base": _mat(table.base), "rows": _named_rows(table.rows, rep.keys, key, degrees, masses),
               "tool": _mat(table.tool)}
    elif rep.layout == "screws":
        out = {"frame": table.frame, "M": _mat(table.M), "screws": _mat(table.screws)}
        if masses is not None:  # mass properties at q = 0 in the PoE's frame, one entry per joint
            out["masses"] = [mass_fields(masses, i, _clean) for i in range(masses.n)]
    else:  # RPY-XYZ: row 0 (world -> base) carries the base body's mass properties
        out = {"rows": _named_rows(table.rows, rep.keys, key, degrees, masses, first=1)}
        if masses is not None and masses.base is not None:
            out["rows"][0].update(mass_fields(masses.base, 0, _clean))
        return out
    if masses is not None and masses.base is not None:  # the base body's, in frame {0}
        out["base_mass"] = mass_fields(masses.base, 0, _clean)
    return out


def table_document(table: Any, degrees: bool = False) -> dict[str, Any]:
    """A robot document (dict) holding one table (DHTable, MDHTable, HayatiTable, PoE, RPYTable or any
    registered one) and its joints (angles in degrees if asked)."""
    doc: dict[str, Any] = {"robkin": DOC_VERSION}
    if degrees:
        doc["angles"] = "degrees"
    doc["joints"] = [_joint_entry(j, degrees) for j in table.joints]
    doc[section_key(table)] = _section(table, degrees)
    return doc


def _named_rows(rows: np.ndarray, keys: tuple[str, ...], section: str, degrees: bool,
                masses: MassRows | None = None, first: int = 0) -> list[dict[str, Any]]:
    """Rows as objects with named keys; rows first.. first + n - 1 with their link's ``m``, ``r``, ``I``
    when the table has ``masses`` (never converted to degrees: they are not angles)."""
    angles = ANGLE_COLUMNS.get(section, ()) if degrees else ()
    out: list[dict[str, Any]] = [{k: _clean(math.degrees(v) if k in angles else v) for k, v in zip(keys, row)}
                                 for row in rows]
    if masses is not None:
        for i in range(masses.n):
            out[first + i].update(mass_fields(masses, i, _clean))
    return out


def dump(doc: Mapping[str, Any], fmt: str = "yaml") -> str:
    """Serialise a document as 'yaml' (flow-style rows and matrices) or 'json' (indented)."""
    if fmt == "json":
        from ..files.jsontext import dumps

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
