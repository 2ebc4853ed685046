"""The optional mass fields of a robot document's rows: reading and writing ``m``, ``r`` and ``I``.

A row of ``dh``, ``mdh``, ``hayati`` or ``rpy_xyz`` (joint rows 1..n) may carry link i's mass
properties in that table's own link frame i (``robkin.representations.mass_rows``):

- ``m``: mass (kg), >= 0;
- ``r``: centre of mass, 3 numbers (x, y, z) in frame i;
- ``I``: inertia about the centre of mass in the axes of frame i, 6 numbers (Ixx, Iyy, Izz, Ixy, Iyz,
  Ixz) in kg m^2.

The base body's (everything fixed to the robot base, in link frame 0) may be given too: as the
section's ``base_mass: {m, r, I}``, or on the row that is the base's (RPY-XYZ's world row 0, the
paper layout's DH row 0). Either every joint row gives ``m`` or none does (absent means unknown, never
zero mass: a massless link says ``m: 0``); a row with ``m`` and no ``r`` or ``I`` has its centre of
mass at the frame origin or no rotational inertia (a point mass), as the Robotics Toolbox's links
default. A row given as a list (column order) carries them as 10 more numbers: m, rx, ry, rz, Ixx,
Iyy, Izz, Ixy, Iyz, Ixz. A ``poe`` section gives them as ``masses: [{m, r, I}, ...]``, one per joint,
at q = 0 in its reference frame (and ``base_mass``).
Mass fields are never angles: ``angles: degrees`` does not touch them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from ...errors import InputError
from ...representations.mass_rows import INERTIA_KEYS, MASS_KEYS, MassRows
from ..files.numbers import number, number_list

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["split_masses", "read_masses", "mass_fields", "same_masses", "mass_columns_at", "mass_cells",
           "add_mass_columns", "LIST_WIDTH"]

#: Numbers a list row adds for its mass properties: m, r (3), I (6).
LIST_WIDTH = 10


def split_masses(rows: Any, key: str, width: int, skip: tuple[int, ...] = (), base_row: int | None = None,
                 base_mass: Any = None) -> tuple[Any, MassRows | None]:
    """Rows as ``document._rows`` reads them (the mass fields taken out) and their ``MassRows``.

    ``width``: the number of kinematic columns of a row; ``skip``: indices of rows that carry no link
    (RPY-XYZ's tool row), left as they are and refused mass fields; ``base_row``: the index of the row
    that is the base body's (RPY-XYZ's world row, the paper layout's DH row 0), whose mass fields are
    the base's; ``base_mass``: the section's ``base_mass`` entry ({m, r, I}) otherwise.
    """
    if not isinstance(rows, list):
        return rows, None
    out: list[Any] = []
    fields: list[tuple[int, Any, Any, Any]] = []  # (row index, m, r, I) of the rows that carry masses
    plain: list[int] = []
    for i, row in enumerate(rows):
        where = f"{key}[{i}]"
        if isinstance(row, Mapping) and any(k in row for k in MASS_KEYS):
            if i in skip:
                raise InputError(f"{where}: this row is not a link's; mass fields (m, r, I) go on joint rows")
            found = [row.get(k) for k in MASS_KEYS]
            out.append({k: v for k, v in row.items() if k not in MASS_KEYS})
        elif isinstance(row, list) and len(row) == width + LIST_WIDTH and i not in skip:
            found = [row[width], row[width + 1:width + 4], row[width + 4:]]
            out.append(row[:width])
        else:
            out.append(row)
            plain.append(i)
            continue
        fields.append((i, *found))
    base_fields = [f for f in fields if f[0] == base_row]
    fields = [f for f in fields if f[0] != base_row]
    where_base = f"{key.split('.')[0]}.base_mass"
    if base_mass is not None:
        if base_row is not None and base_fields:
            raise InputError(f"{where_base}: the base's mass is given twice (also on {key}[{base_row}])")
        base_fields = [(-1, *_base_entry(base_mass, where_base))]
    links = [i for i in range(len(rows)) if i not in skip and i != base_row]
    if not fields:
        if base_fields:
            raise InputError(f"{where_base if base_mass is not None else f'{key}[{base_row}]'}: the base's mass "
                             f"properties need those of every link too (m on every joint row)")
        return out, None
    missing = [i for i in plain if i in links]
    if missing:
        raise InputError(f"{key}[{missing[0]}]: no m, but other rows give mass properties; give m (kg) on "
                         f"every joint row (m: 0 for a massless link) or on none")
    base = _mass_rows(base_fields, key if base_mass is None else where_base) if base_fields else None
    rows_masses = _mass_rows(fields, key)
    return out, MassRows(rows_masses.mass, rows_masses.com, rows_masses.inertia, base)


def _base_entry(value: Any, where: str) -> tuple[Any, Any, Any]:
    """(m, r, I) of a ``base_mass`` mapping."""
    if not isinstance(value, Mapping):
        raise InputError(f"{where}: expected a mapping {{m: kg, r: [x, y, z], I: [{', '.join(INERTIA_KEYS)}]}}")
    extra = sorted(str(k) for k in value if k not in MASS_KEYS)
    if extra:
        raise InputError(f"{where}: unknown key(s) {', '.join(extra)}; known: m, r, I")
    return value.get("m"), value.get("r"), value.get("I")


def _mass_rows(fields: list[tuple[int, Any, Any, Any]], key: str) -> MassRows:
    mass, com, six = [], [], []
    for i, m, r, I in fields:
        where = key if i < 0 else f"{key}[{i}]"
        if m is None:
            raise InputError(f"{where}.m: missing; a row with r or I needs its mass m (kg)")
        mass.append(number(m, f"{where}.m"))
        com.append([0.0, 0.0, 0.0] if r is None else _numbers(r, f"{where}.r", ("x", "y", "z")))
        six.append([0.0] * 6 if I is None else _numbers(I, f"{where}.I", INERTIA_KEYS))
    return _checked(mass, com, six, key, [i for i, *_ in fields])


def _numbers(value: Any, field: str, names: tuple[str, ...]) -> list[float]:
    """``len(names)`` numbers; the error names what they are (``I: expected 6 numbers (Ixx, ...)``)."""
    if isinstance(value, (list, tuple)) and len(value) != len(names):
        raise InputError(f"{field}: expected {len(names)} numbers ({', '.join(names)}), got {len(value)}")
    return number_list(value, field, len(names))


def _checked(mass: list[float], com: list[list[float]], six: list[list[float]], key: str,
             index: list[int]) -> MassRows:
    """MassRows of the numbers read, an InputError naming the row where they are not valid."""
    for k, (m, r, I) in enumerate(zip(mass, com, six)):
        where = key if index[k] < 0 else f"{key}[{index[k]}]"
        for name, values in (("m", [m]), ("r", r), ("I", I)):
            if not all(np.isfinite(values)):
                raise InputError(f"{where}.{name}: must be finite numbers")
        if m < 0:
            raise InputError(f"{where}.m: {m!r} kg; a mass is >= 0")
    return MassRows.from_six(mass, com, six)


def read_masses(value: Any, key: str, n: int, base_mass: Any = None) -> MassRows | None:
    """A PoE section's ``masses`` list ({m, r, I} per joint) and ``base_mass``, or None when absent."""
    where_base = f"{key.split('.')[0]}.base_mass"
    if value is None:
        if base_mass is not None:
            raise InputError(f"{where_base}: the base's mass properties need those of every link too (masses)")
        return None
    if not isinstance(value, list) or len(value) != n:
        raise InputError(f"{key}: expected a list of {n} entries {{m, r, I}}, one per joint")
    fields = []
    for i, entry in enumerate(value):
        if not isinstance(entry, Mapping):
            raise InputError(f"{key}[{i}]: expected a mapping {{m: kg, r: [x, y, z], I: [{', '.join(INERTIA_KEYS)}]}}")
        extra = sorted(str(k) for k in entry if k not in MASS_KEYS)
        if extra:
            raise InputError(f"{key}[{i}]: unknown key(s) {', '.join(extra)}; known: m, r, I")
        fields.append((i, entry.get("m"), entry.get("r"), entry.get("I")))
    rows = _mass_rows(fields, key)
    base = None if base_mass is None else _mass_rows([(-1, *_base_entry(base_mass, where_base))], where_base)
    return MassRows(rows.mass, rows.com, rows.inertia, base)


def mass_fields(masses: MassRows, i: int, clean: Any) -> dict[str, Any]:
    """Row i's ``m``, ``r`` and ``I`` as a document writes them (each float through ``clean``)."""
    return {"m": clean(masses.mass[i]), "r": [clean(v) for v in masses.com[i]],
            "I": [clean(v) for v in masses.six[i]]}


def same_masses(a: "Robot", b: "Robot", tol: float) -> str | None:
    """None if two descriptions of one robot give the same mass properties per link (mass relative to
    the total, centre of mass relative to the robot's size, inertia relative to the largest entry, all
    within ``tol``), else which link differs and how."""
    from ...mass_properties import link_masses

    ma, mb = link_masses(a), link_masses(b)
    if ma is None or mb is None:
        return None if ma is mb else "one gives mass properties, the other none"
    scale = max(a.scale, b.scale)
    total = max(float(ma.mass.sum()), float(mb.mass.sum()), 1e-300)
    big = max(float(np.abs(ma.inertia).max()), float(np.abs(mb.inertia).max()), 1e-300)
    # the base body (0) where both give it (it never changes the joint torques)
    both = all(any(p.body == 0 for p in r.bodies.inertials) for r in (a, b))
    for i in range(0 if both else 1, a.n + 1):
        for what, x, y, ref in (("mass", ma.mass[i], mb.mass[i], total),
                                ("centre of mass", ma.com[i], mb.com[i], scale),
                                ("inertia", ma.inertia[i], mb.inertia[i], big)):
            d = float(np.abs(np.asarray(x) - np.asarray(y)).max())
            if d > tol * ref:
                name = "the base" if i == 0 else f"link {i} ({a.joints[i - 1].name})"
                return f"{name}: {what} differs by {d:.3g}"
    return None


def mass_columns_at(header: list[str], after: int) -> int | None:
    """Where the ten mass columns (``io.tables.files.MASS_COLUMNS``: ``m (kg)``, ``rx (m)``, ...,
    ``Ixz (kg m^2)``) start in a table file's header, looking from column ``after`` on; None without them."""
    from ..tables.files import MASS_COLUMNS

    names = [c.lower() for c, _ in MASS_COLUMNS]
    lowered = [h.strip().lower() for h in header]
    for k in range(after, len(lowered) - len(names) + 1):
        if lowered[k:k + len(names)] == names:
            return k
    return None


def mass_cells(cells: list[str], at: int | None, line: int, header: list[str]) -> list[float] | None:
    """A table file row's ten mass values (m, rx, ry, rz, Ixx, ..., Ixz) from column ``at``, or None
    when the row leaves them empty (RPY-XYZ's tool row) or the file has none."""
    if at is None:
        return None
    values = [c.strip() for c in cells[at:at + LIST_WIDTH]]
    if not any(values):
        return None
    if len(values) < LIST_WIDTH or not all(values):
        raise InputError(f"line {line}: the mass columns ({', '.join(header[at:at + LIST_WIDTH])[:60]}...) need "
                         f"all ten values, or none")
    return [number(v, f"line {line}, column {header[at + j]}") for j, v in enumerate(values)]


def add_mass_columns(section: dict[str, Any], masses: list[list[float] | None]) -> None:
    """A table file's mass columns into its document section (in place): 10 more numbers on each row
    of ``rows`` that has them (``split_masses`` reads them), or a PoE's ``masses`` list."""
    if not any(m is not None for m in masses):
        return
    if "screws" in section:
        if any(m is None for m in masses):
            raise InputError("a PoE table's mass columns need values on every joint row, or none")
        section["masses"] = [{"m": m[0], "r": m[1:4], "I": m[4:]} for m in masses if m is not None]
    elif "rows" in section:
        section["rows"] = [row if m is None else [*row, *m] for row, m in zip(section["rows"], masses)]
