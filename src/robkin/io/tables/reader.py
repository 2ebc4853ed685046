"""Tables as input: the CSV files ``robkin convert --format csv`` writes, and bare rows of numbers.

Two kinds of file are read (``.csv``, ``.tsv``, ``.txt``):

* a table with a header row, as robkin writes it: label columns (``i``, ``joint``, ``type``; for
  RPY-XYZ ``row``, ``frame``, ``type``) then one representation's columns, whose names say which
  representation it is (``a, d, alpha, theta`` standard DH; ``a(i-1), d, alpha(i-1), theta`` modified
  DH; ``+ beta`` Hayati; ``wx .. vz`` PoE; ``roll .. z`` RPY-XYZ; ``m11 .. m34`` GJD); after an empty
  line, the fixed transforms as rows ``name, m11, ..., m34`` (``base``/``tool``, or ``M``). Only the
  representation columns are needed (a header ``a,d,alpha,theta`` alone will do); the label columns
  give the joint names and types (``revolute``, ``prismatic``, ``revolute (flip)``). Values may be
  expressions such as ``-pi/2`` (what ``--pi`` writes). The ten mass columns robkin writes after the
  representation's (``m (kg)``, ``rx (m)``, ..., ``Ixz (kg m^2)``) are read as each link's mass
  properties in the table's link frame (RPY-XYZ's world row: the base's; see ``io.documents.masses``).
  A first row whose representation cells are empty (``0, (base), fixed, , , , , m, rx, ...``) is the base
  body's: its mass columns are the base's, in link frame 0 (the document's ``base_mass``). A text cell
  robkin wrote with a leading ``'`` against spreadsheet formulas (``'=x``) is read as the
  name itself (``=x``; ``io.tables.cells``);
* bare rows (no header), as pasted from a paper and as the GUI takes them
  (``robkin.io.tables.pasted``): ``a d alpha theta [R|P]`` per line, and so on.

Where the file does not say (bare rows; plain ``a, d, alpha, theta`` could be either DH; a PoE's
screws are space or body frame), ``representation`` (the CLI's ``--from``) says; where the file
says, ``representation`` must agree with it.
"""

from __future__ import annotations

import csv
import os
import re
import warnings
from typing import Any, Sequence

from ...errors import InputError
from ...representations.registry import LiveNames, by_name, names, representations
from ...robot import Robot
from ..documents.masses import LIST_WIDTH, add_mass_columns, mass_cells, mass_columns_at
from ..files.numbers import number
from .cells import csv_read_cell
from ...compiled.scanners.vocabulary import MAX_JOINTS

__all__ = ["TABLE_INPUT_EXTENSIONS", "TABLE_INPUTS", "read_table_file", "table_document"]

TABLE_INPUT_EXTENSIONS = (".csv", ".tsv", ".txt")
#: ``--from`` choices: representations a table file can hold (a live view of the registry)
TABLE_INPUTS = LiveNames(lambda: names("csv"))
#: Largest table file read: a table of a few hundred joints is tens of kB; this bounds memory.
MAX_BYTES = 16 * 1024 * 1024


def _columns() -> dict[str, tuple[str, ...]]:
    """Header columns of each representation (names as robkin writes them), longest first where one
    set begins another (Hayati's five columns start with DH's four); of representations with the
    same columns (PoE's two frames), the first registered."""
    out: list[tuple[str, tuple[str, ...]]] = []
    for rep in representations():
        if "csv" not in rep.file_formats or any(h == rep.headers for _, h in out):
            continue
        # before the first one whose columns begin its own (else that one would match first)
        at = next((k for k, (_, h) in enumerate(out) if rep.headers[:len(h)] == h), len(out))
        out.insert(at, (rep.name, rep.headers))
    return dict(out)


def _fits(found: str) -> tuple[str, ...]:
    """The representations a header of ``found``'s columns may hold: those with the same headers
    (PoE in either frame), or whose document keys are those headers (plain a, d, alpha, theta: DH or
    modified DH)."""
    headers = by_name(found).headers
    return tuple(r.name for r in representations() if "csv" in r.file_formats
                 and (r.headers == headers or r.keys == headers))


def read_table_file(path: str | os.PathLike[str], representation: str | None = None) -> Robot:
    """The robot in a table file (see the module); InputError naming the file, line and column."""
    from ..documents.reader import robot_from_data
    from ..files.input_files import read_text_file

    p = os.fspath(path)
    text = read_text_file(p, MAX_BYTES, "a table")
    try:
        data = table_document(text, representation, tab=p.lower().endswith(".tsv"))
    except InputError as exc:
        raise exc.in_source(p) from None
    data["name"] = os.path.splitext(os.path.basename(p))[0]
    return robot_from_data(data, source=p)


def table_document(text: str, representation: str | None = None, tab: bool = False) -> dict[str, Any]:
    """A robot document (dict) from a table's text: a header table or bare rows (see the module)."""
    if representation is not None and representation not in TABLE_INPUTS:
        raise InputError(f"representation='{representation}' is not one of {', '.join(TABLE_INPUTS)}")
    lines = text.splitlines()
    first = next((line for line in lines if line.strip() and not line.lstrip().startswith("#")), None)
    if first is None:
        raise InputError("no rows; a table file holds a header row and one row per joint, or bare rows")
    # bare rows may be separated by spaces, tabs, commas or semicolons; a header starts with a name
    cells = [c for c in re.split(r"[\s,;]+", first.strip()) if c]
    if cells and not _is_number(cells[0]):
        return _header_document(lines, representation, tab)
    return _bare_document(text, representation)


def _split(line: str, tab: bool) -> list[str]:
    """A line's cells; a text cell robkin wrote with a ``'`` against spreadsheet formulas (``'=x``)
    back to its name (``io.tables.cells``)."""
    return [csv_read_cell(c.strip()) for c in next(csv.reader([line], delimiter="\t" if tab else ","))]


def _is_number(cell: str) -> bool:
    try:
        number(cell, "")
    except InputError:
        return False
    return True


def _bare_document(text: str, representation: str | None) -> dict[str, Any]:
    from .pasted import document_from_table

    fmt = {"dh": "dh-rows", "mdh": "mdh-rows", "poe": "poe-rows", "rpy-xyz": "rpy-rows"}.get(representation or "")
    if fmt is None:
        if representation is None:
            raise InputError("bare rows of numbers do not say which table they are: give representation= "
                             "dh, mdh, poe or rpy-xyz (rows 'a d alpha theta [R|P]', 'wx wy wz vx vy vz "
                             "[R|P]' then 'M ...', or n + 2 rows 'roll pitch yaw x y z')")
        raise InputError(f"representation='{representation}': bare rows are read as dh, mdh, poe or rpy-xyz; "
                         f"a {representation} table needs a header row (as robkin convert --format csv writes)")
    return document_from_table(text, fmt)


def _find_columns(header: Sequence[str]) -> tuple[str, int]:
    """The representation whose column names appear in the header (in order) and where they start."""
    lowered = [h.lower() for h in header]
    columns = _columns()
    for rep, cols in columns.items():
        for start in range(len(lowered) - len(cols) + 1):
            if tuple(lowered[start:start + len(cols)]) == cols:
                return rep, start
    known = "; ".join(", ".join(c) for rep, c in columns.items() if by_name(rep).layout != "frames") \
        + "; m11, ..., m34"
    raise InputError(f"line 1: the header names no table's columns ({', '.join(header)[:80]}); expected one of: "
                     f"{known}")


def _settle(rep: str, representation: str | None) -> str:
    """The representation, from the header (``rep``) and the caller's ``representation``."""
    fits = _fits(rep)
    if representation is None:
        same = [r for r in fits if by_name(r).headers == by_name(rep).headers]
        if len(same) > 1 and by_name(rep).layout == "screws":
            raise InputError("the header's screw columns do not say which frame: give representation= "
                             + " or ".join(f"{r} (space frame)" if by_name(r).from_robot_args == ("space",) else r
                                           for r in same))
        if len(same) > 1:
            raise InputError(f"the header's columns do not say which table: give representation= "
                             f"{' or '.join(same)}")
        return rep
    if representation == rep or representation in fits:
        return representation
    raise InputError(f"representation='{representation}' does not fit the header, which has {rep} columns "
                     f"({', '.join(by_name(rep).headers)})")


def _joint(labels: dict[str, str], k: int) -> dict[str, Any]:
    """A document joint from a row's label cells (joint name, 'revolute (flip)')."""
    kind = labels.get("type", "").lower().strip() or "revolute"
    flip = kind.endswith("(flip)")
    kind = kind.removesuffix("(flip)").strip()
    kind = {"r": "revolute", "p": "prismatic"}.get(kind, kind)
    name = labels.get("joint") or labels.get("frame") or labels.get("name") or f"joint{k + 1}"
    return {"name": name, "type": kind, "flip": flip}


def _header_document(lines: list[str], representation: str | None, tab: bool) -> dict[str, Any]:
    numbered = [(k, line) for k, line in enumerate(lines, start=1) if not line.lstrip().startswith("#")]
    # the table: the header and the rows up to the first empty line; then the transforms
    while numbered and not numbered[0][1].strip():
        numbered.pop(0)
    head_no, head_line = numbered[0]
    header = _split(head_line, tab)
    found, start = _find_columns(header)
    rep = _settle(found, representation)
    cols = by_name(found).headers
    labels_at = {h.lower(): i for i, h in enumerate(header[:start])}
    mass_at = mass_columns_at(header, start + len(cols))  # m (kg), rx (m), ... as robkin writes them
    extra = [h for i, h in enumerate(header[start + len(cols):], start + len(cols))
             if h and (mass_at is None or not mass_at <= i < mass_at + LIST_WIDTH)]
    if extra:
        warnings.warn(f"columns {', '.join(extra)[:80]} are not part of the {rep} table and are ignored")
    rows: list[list[float]] = []
    masses: list[list[float] | None] = []
    joints: list[dict[str, Any]] = []
    rest = numbered[1:]
    body: list[tuple[int, list[str]]] = []
    for idx, (k, line) in enumerate(rest):
        if not line.strip() or not any(c for c in _split(line, tab)):
            rest = rest[idx + 1:]
            break
        if len(body) > MAX_JOINTS + 2:  # + 2: the frames of an RPY-XYZ table (checked before any parse)
            raise InputError(f"line {k}: more than {MAX_JOINTS} joints (one row each); at most {MAX_JOINTS} are read")
        body.append((k, _split(line, tab)))
    else:
        rest = []
    base_mass = None
    if body and not any(c.strip() for c in body[0][1][start:start + len(cols)]):
        base_mass = _base_row(body.pop(0), rep, mass_at, header)
    for k, cells in body:
        if len(cells) < start + len(cols):
            raise InputError(f"line {k}: expected {start + len(cols)} columns ({', '.join(header[:start + len(cols)])}), "
                             f"got {len(cells)}")
        rows.append([number(c, f"line {k}, column {header[start + j]}") for j, c in enumerate(cells[start:start + len(cols)])])
        joints.append(_joint({name: cells[i] for name, i in labels_at.items()}, len(joints)))
        masses.append(mass_cells(cells, mass_at, k, header))
    transforms = _transforms(rest, tab)
    doc = _document(rep, rows, joints, transforms)
    add_mass_columns(doc[by_name(rep).section], masses)
    if base_mass is not None:
        doc[by_name(rep).section]["base_mass"] = {"m": base_mass[0], "r": base_mass[1:4], "I": base_mass[4:]}
    return doc


def _base_row(row: tuple[int, list[str]], rep: str, mass_at: int | None, header: list[str]) -> list[float]:
    """The base body's ten mass values from the first row when its representation cells are empty
    (``io.tables.files.BASE_LABELS``: DH, MDH, Hayati and PoE tables write it so); InputError when
    such a row has no mass values or belongs to a table that carries the base's otherwise."""
    k, cells = row
    if by_name(rep).layout not in ("link-table", "screws"):
        raise InputError(f"line {k}: the {rep} columns are empty; a {rep} table has a value in each of them on "
                         f"every row" + (" (its world row carries the base's mass)" if by_name(rep).layout == "rpy"
                                         else ""))
    values = mass_cells(cells, mass_at, k, header)
    if values is None:
        raise InputError(f"line {k}: the {rep} columns are empty; only the base's row (row 0) leaves them empty, "
                         f"and it carries the base's mass columns (m (kg), rx (m), ...)")
    return values


def _transforms(numbered: list[tuple[int, str]], tab: bool) -> dict[str, list[list[float]]]:
    """The fixed transforms after the table: rows 'name, m11, ..., m34' (a 'transform' header first)."""
    out: dict[str, list[list[float]]] = {}
    for k, line in numbered:
        cells = _split(line, tab)
        if not any(cells) or cells[0].lower() == "transform":
            continue
        name = cells[0]
        if len(cells) != 13:
            raise InputError(f"line {k}: transform '{name[:40]}': expected its name and 12 numbers "
                             f"(m11 .. m34, the 3 x 4 block [R | p] row by row), got {len(cells) - 1}")
        v = [number(c, f"line {k}, transform '{name[:40]}'") for c in cells[1:]]
        out[name] = [v[0:4], v[4:8], v[8:12], [0.0, 0.0, 0.0, 1.0]]
    return out


def _document(rep: str, rows: list[list[float]], joints: list[dict[str, Any]],
              transforms: dict[str, list[list[float]]]) -> dict[str, Any]:
    """The robot document of the table's rows, joints and fixed transforms."""
    if not rows:
        raise InputError("no rows after the header; one row per joint")
    section: dict[str, Any]
    wanted: tuple[str, ...]
    spec = by_name(rep)
    if spec.layout == "link-table":
        wanted = ("base", "tool")
        section = {"rows": rows, **{k: v for k, v in transforms.items() if k in wanted}}
    elif spec.layout == "screws":
        wanted = ("M",)
        if "M" not in transforms:
            raise InputError("a PoE table needs its home tool pose: a row 'M, m11, ..., m34' after an empty line")
        section = {"frame": spec.from_robot_args[0] if spec.from_robot_args else "space", "M": transforms["M"],
                   "screws": rows}
    elif spec.layout == "rpy":
        wanted = ()
        if len(rows) < 3:
            raise InputError(f"{len(rows)} rows; an RPY-XYZ table has n + 2 rows (world->base, one per joint, "
                             f"joint n->tool)")
        joints = joints[1:-1]
        section = {"rows": rows}
    else:  # gjd: n joint frames then the tool frame
        wanted = ()
        if len(rows) < 2:
            raise InputError("a GJD table has n + 1 rows (the joint frames, then the tool frame)")
        joints = joints[:-1]
        section = {"frames": [[r[0:4], r[4:8], r[8:12], [0.0, 0.0, 0.0, 1.0]] for r in rows]}
    unknown = [k for k in transforms if k not in wanted]
    if unknown:
        raise InputError(f"transform '{unknown[0][:40]}' does not belong to a {rep} table"
                         + (f" (it has {', '.join(wanted)})" if wanted else " (it has none)"))
    for j in joints:  # the first and last rows of an RPY-XYZ or GJD table are frames, not joints
        if j["type"] not in ("revolute", "prismatic"):
            raise InputError(f"joint '{j['name'][:40]}': type '{j['type'][:40]}' is not revolute or prismatic")
    return {"robkin": 1, "joints": joints, spec.section: section}
