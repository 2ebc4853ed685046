"""Tables for papers and spreadsheets: a representation as CSV, Markdown or LaTeX, full precision.

Every number is written as the shortest decimal that reproduces it to the FK budget of exact
conversions (``rounding.SNAP_BUDGET``: the whole table moves the tool by at most 1e-12 of the robot's
size; ``float_text.decimal_tolerances``), so 0.3839999999999999 is written 0.384 and -4.16e-18 is 0;
``digits=N`` writes N significant digits instead, and ``digits="exact"`` every digit (``repr``: reads
back to the same float). With ``pi=True`` an angle that is exactly a multiple of pi (``-pi/2``,
``3*pi/4``) is written as such (evaluating the text ``k*pi/m`` gives back the very same number;
1.57079632679 typed into a URDF is not pi/2 and stays a decimal). Lengths are in the robot's unit
(normally metres), angles in radians.

Layout (the same content in each format)
    the joint rows: index, joint name, type, then the representation's columns (DH: a, d, alpha,
    theta; MDH: a(i-1), d, alpha(i-1), theta; PoE: wx, wy, wz, vx, vy, vz; RPY-XYZ: n + 2 rows of
    roll, pitch, yaw, x, y, z; GJD: the 3 x 4 block of each frame); then the fixed transforms that
    complete the table (DH/MDH/Hayati: base and tool; PoE: M), each as its 3 x 4 block [R | p]
    row-major. CSV puts those after an empty line, in rows ``name,m11,m12,m13,m14,m21,...,m34``.

Text cells (names from the robot file) are made inert (``io.tables.cells``): in CSV a cell starting
with ``= + - @``, tab or CR gets a leading ``'`` (no spreadsheet formula; the reader drops it again),
in Markdown HTML and link/emphasis markup are escaped.

Mass properties
    When the robot has them, each joint row ends with ten more columns: ``m (kg)``, ``rx (m)``,
    ``ry (m)``, ``rz (m)``, ``Ixx (kg m^2)``, ``Iyy``, ``Izz``, ``Ixy``, ``Iyz``, ``Ixz`` (the same
    unit): link i's mass, centre of mass and inertia about it, in the table's own link frame i
    (``robkin.representations.mass_rows``). The base body's (frame {0}), when known, is on a row of its
    own before joint 1's in DH, MDH, Hayati and PoE tables: ``0, (base), fixed`` with the
    representation's cells empty (``BASE_LABELS``; the reader takes it back as ``base_mass``); on
    RPY-XYZ's world row, whose tool row leaves them empty. LaTeX puts the mass columns in tabulars of
    their own (m and r; I's diagonal; I's products) so that a 7-joint arm fits an A4 page.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ...errors import InputError
from ...representations.registry import LiveNames, by_name, names, representations
from ...robot import Robot
from ..files.float_text import decimal_tolerances, digits_text, short_text
from ..files.float_text import float_text as _num
from .cells import csv_text_cell, md_text_cell

if TYPE_CHECKING:  # pragma: no cover
    from ...representations.mass_rows import MassRows

__all__ = ["TABLE_FORMATS", "TABLE_EXTENSIONS", "TABLE_REPRESENTATIONS", "Table", "table_of", "render_table",
           "pi_text"]

TABLE_FORMATS = ("csv", "markdown", "latex")
TABLE_EXTENSIONS = {"csv": ".csv", "markdown": ".md", "latex": ".tex"}
#: Representations with a table form (registered as writable in CSV; a live view of the registry).
TABLE_REPRESENTATIONS = LiveNames(lambda: names("csv"))
#: Denominators tried for multiples of pi: every angle a table of a real robot has in closed form
#: (pi/2, pi/3, pi/4, pi/6, pi/12, ...). Numerators up to 2 * denominator (one full turn).
PI_DENOMINATORS = (1, 2, 3, 4, 6, 8, 12)
_BLOCK = [f"m{r}{c}" for r in (1, 2, 3) for c in (1, 2, 3, 4)]
#: The label cells of the base body's row in DH, MDH, Hayati and PoE tables (index 0, before joint 1's):
#: it carries the base's mass properties and leaves the kinematic columns empty (the base is no joint;
#: its pose is the ``base`` transform). RPY-XYZ's world row carries them instead.
BASE_LABELS = ("0", "(base)", "fixed")


@dataclass
class Table:
    """One representation as a table: columns (name, LaTeX header, whether it is an angle), rows
    (labels then numbers), and the fixed transforms (name, (4, 4)) that complete it.

    ``tolerances`` (length units, radians) are how far a written value may lie from the float
    (``short_text``); (0, 0) writes every digit. ``digits`` (if set) writes that many significant
    digits instead.
    """

    title: str
    labels: Sequence[str]
    columns: Sequence[tuple[str, str, bool]]
    rows: list[tuple[list[str], list[float]]]
    transforms: list[tuple[str, np.ndarray]] = field(default_factory=list)
    tolerances: tuple[float, float] = (0.0, 0.0)
    digits: int | None = None
    #: the mass columns' own tolerances (``with_mass_columns``), used whenever ``tolerances`` are
    mass_tolerances: dict[str, float] = field(default_factory=dict)

    def text(self, x: float, column: str) -> str:
        """A value of column ``column`` (a name of ``columns``, or m11..m34 of a transform) as text."""
        kind = _kind(column)
        if kind is None and (column not in self.mass_tolerances or self.tolerances == (0.0, 0.0)):
            return _num(x)  # a column of another kind, or every digit asked for
        tol = self.mass_tolerances[column] if kind is None else self.tolerances[0 if kind == "length" else 1]
        if self.digits is not None:  # rounding noise is 0 at any number of digits
            return "0" if abs(x) <= tol else digits_text(x, self.digits)
        return short_text(x, tol)


def _kind(column: str) -> str | None:
    """The kind of a column robkin writes (by its header): a 'length' (robot units) or an 'angle'-like
    value (radians, or a unit direction / rotation entry, whose error turns the chain like an angle),
    as its representation declares it (``robkin.representations.registry``); None for other columns."""
    for rep in representations():
        for c in rep.columns:
            if c.header == column:
                return "length" if c.kind == "length" else "angle"
    return None


def pi_text(x: float) -> str | None:
    """``k*pi/m`` (as 'pi', '-pi/2', '3*pi/4') when x is exactly that float, else None."""
    if x == 0 or not math.isfinite(x):
        return None
    for m in PI_DENOMINATORS:
        k = round(x * m / math.pi)
        if k == 0 or abs(k) > 2 * m or math.gcd(k, m) != 1:
            continue
        if k * math.pi / m == x:
            sign, k = ("-" if k < 0 else ""), abs(k)
            return sign + ("" if k == 1 else f"{k}*") + "pi" + ("" if m == 1 else f"/{m}")
    return None


def _tex(text: str) -> str:
    """A number's text for LaTeX math: 1.5e-12 as 1.5 \\times 10^{-12}."""
    mantissa, e, exponent = text.partition("e")
    return f"{mantissa} \\times 10^{{{int(exponent)}}}" if e else text


def _cell(t: Table, x: float, column: tuple[str, str, bool], pi: bool) -> str:
    if math.isnan(x):  # a row without this column's quantity (RPY-XYZ's tool row: no mass)
        return ""
    if pi and column[2]:
        text = pi_text(float(x))
        if text is not None:
            return text
    return t.text(x, column[0])


def _block_text(t: Table, T: np.ndarray) -> list[str]:
    """The 3 x 4 block [R | p] of a transform, row-major, as text."""
    return [t.text(v, m) for v, m in zip(np.asarray(T)[:3].ravel(), _BLOCK)]


def with_precision(t: Table, robot: Robot, digits: int | str | None = None) -> Table:
    """``t`` set to write its numbers to the FK budget (``digits=None``), with ``digits`` significant
    digits (an int), or bit-exact (``digits='exact'``)."""
    from ...representations.rounding import SNAP_BUDGET

    if digits == "exact":
        return t
    t.digits = None if digits is None else int(digits)
    lengths = [abs(v) for _, values in t.rows for v, c in zip(values, t.columns)
               if _kind(c[0]) == "length" and not math.isnan(v)]  # NaN: an empty cell (the base row's)
    lengths += [float(np.linalg.norm(np.asarray(T)[:3, 3])) for _, T in t.transforms]
    # the kinematic budget's share per value; the base row (no kinematic values) takes no share
    count = sum(list(lab) != list(BASE_LABELS) for lab, _ in t.rows) * len(t.columns) + 12 * len(t.transforms)
    t.tolerances = decimal_tolerances(robot.scale, robot.scale + float(sum(lengths)), count, SNAP_BUDGET)
    return t


def _joint_labels(robot: Robot) -> list[list[str]]:
    return [[str(i + 1), j.name, j.type + (" (flip)" if j.flip else "")] for i, j in enumerate(robot.joints)]


def table_of(robot: Robot, rep: str) -> Table:
    """The robot in representation ``rep`` (one of TABLE_REPRESENTATIONS) as a ``Table``, laid out by its
    layout (``robkin.representations.registry``)."""
    if rep not in TABLE_REPRESENTATIONS:
        raise InputError(f"'{rep}' has no table form; tables exist for {', '.join(TABLE_REPRESENTATIONS)}")
    r = by_name(rep)
    title = f"{robot.name or 'robot'}: {r.title}"
    jl = _joint_labels(robot)
    cols = [(c.header, c.latex, c.angle) for c in r.columns]
    if r.layout == "frames":  # n joint frames then the tool frame, each as its 3 x 4 block
        labels = jl + [[str(robot.n + 1), "tool", ""]]
        return Table(title, ["i", "frame", "type"], cols,
                     [(lab, list(map(float, F[:3].ravel()))) for lab, F in zip(labels, r.table_of(robot))])
    t = r.table_of(robot)
    # the base body's row (row 0: its mass properties, no kinematic values) when the table knows them
    base = [(list(BASE_LABELS), [math.nan] * len(cols))] if t.masses is not None and t.masses.base is not None else []
    if r.layout == "link-table":
        return with_mass_columns(Table(title, ["i", "joint", "type"], cols,
                                       base + [(lab, list(map(float, row))) for lab, row in zip(jl, np.asarray(t.rows))],
                                       [("base", t.base), ("tool", t.tool)]), t.masses, first=len(base))
    if r.layout == "screws":
        return with_mass_columns(Table(title, ["i", "joint", "type"], cols,
                                       base + [(lab, list(map(float, s))) for lab, s in zip(jl, t.screws)],
                                       [("M", t.M)]), t.masses, first=len(base))
    labels = [["0", "world->base", ""]] + jl + [[str(robot.n + 1), "tool", ""]]  # rpy: n + 2 rows
    return with_mass_columns(Table(title, ["row", "frame", "type"], cols,
                                   [(lab, list(map(float, row))) for lab, row in zip(labels, t.rows)]),
                             t.masses, first=1)


#: The mass-property columns a table gains when its robot has mass properties: (CSV/Markdown header,
#: LaTeX header); units in the headers (kg, the robot's length unit (normally m), kg m^2).
MASS_COLUMNS = (("m (kg)", "$m$ (kg)"),
                *((f"r{a} (m)", f"$r_{a}$ (m)") for a in "xyz"),
                *((f"I{a} (kg m^2)", f"$I_{{{a}}}$ (kg\\,m$^2$)") for a in ("xx", "yy", "zz", "xy", "yz", "xz")))


def with_mass_columns(t: Table, masses: "MassRows | None", first: int = 0) -> Table:
    """``t`` with the mass columns added to rows first.. first + n - 1 (link i's m, r, I in the table's
    own link frame i, see ``representations.mass_rows``) and the base body's to row first - 1 (RPY-XYZ's
    world row) when known, the other rows' cells empty (NaN); ``t`` itself when there are no mass
    properties."""
    if masses is None:
        return t
    from ...representations.mass_rows import six_from_tensor

    mass, com, inertia = masses.bodies()  # bodies 0..n: body 0 on the row before the first link's, if any
    values = np.column_stack([mass, com, six_from_tensor(inertia)])
    rows = []
    for k, (lab, row) in enumerate(t.rows):
        known = 0 <= k - first < masses.n or (k == first - 1 and masses.base is not None)
        extra = values[k - first + 1] if known else np.full(len(MASS_COLUMNS), np.nan)
        rows.append((lab, row + [float(v) for v in extra]))
    # shortest decimals within 1e-12 of the largest mass, of the robot's size (centres; the table's
    # largest length stands in for it) and of the largest inertia entry, the FK budget of the table's
    # own numbers: the mass matrix and gravity torques move by ~1e-11 of their largest entry at most,
    # far inside the 1e-9 the round trips promise, while the noise of the frame changes goes (UR5's
    # -0.0929999999998: its URDF's 4.9e-12 rad tilt times the link's length)
    size = max([abs(v) for _, vals in t.rows for v, c in zip(vals, t.columns)
                if _kind(c[0]) == "length" and not math.isnan(v)]
               + [float(np.linalg.norm(np.asarray(T)[:3, 3])) for _, T in t.transforms] + [1e-300])
    scales = [float(np.abs(mass).max()), size, size, size, *[float(np.abs(inertia).max())] * 6]
    tolerances = {c: 1e-12 * ref for (c, _), ref in zip(MASS_COLUMNS, scales)}
    return Table(t.title, t.labels, [*t.columns, *((c, tex, False) for c, tex in MASS_COLUMNS)], rows,
                 t.transforms, mass_tolerances=tolerances)


def to_csv(t: Table, pi: bool = False) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    # text cells (names from the robot file) never start a spreadsheet formula; numbers stay numbers
    w.writerow([csv_text_cell(s) for s in t.labels] + [c[0] for c in t.columns])
    for lab, values in t.rows:
        w.writerow([csv_text_cell(s) for s in lab] + [_cell(t, v, c, pi) for v, c in zip(values, t.columns)])
    if t.transforms:
        w.writerow([])
        w.writerow(["transform"] + _BLOCK)
        for name, T in t.transforms:
            w.writerow([csv_text_cell(name)] + _block_text(t, T))
    return buf.getvalue()


def _md_escape(s: str) -> str:
    """A text cell (a name from the robot file): no HTML, link, image or emphasis markup gets through."""
    return md_text_cell(s)


def to_markdown(t: Table, pi: bool = False) -> str:
    heads = list(t.labels) + [c[0] for c in t.columns]
    align = [":--"] * len(t.labels) + ["--:"] * len(t.columns)
    out = [f"**{_md_escape(t.title)}**", "", "| " + " | ".join(heads) + " |", "|" + "|".join(align) + "|"]
    for lab, values in t.rows:
        cells = [_md_escape(s) for s in lab] + [_cell(t, v, c, pi) for v, c in zip(values, t.columns)]
        out.append("| " + " | ".join(cells) + " |")
    for name, T in t.transforms:
        out += ["", f"{name} [R | p]:", "", "| | 1 | 2 | 3 | 4 |", "|:--|--:|--:|--:|--:|"]
        block = _block_text(t, T)
        out += [f"| {r + 1} | " + " | ".join(block[4 * r:4 * r + 4]) + " |" for r in range(3)]
    return "\n".join(out) + "\n"


_TEX = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_",
        "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}


def _tex_text(s: str) -> str:
    return "".join(_TEX.get(c, c) for c in s)


def _tex_num(table: Table, x: float, column: tuple[str, str, bool], pi: bool) -> str:
    if math.isnan(x):  # no quantity in this row (see _cell)
        return ""
    t = pi_text(float(x)) if pi and column[2] else None
    if t is None:
        return f"${_tex(table.text(x, column[0]))}$"
    sign, body = ("-", t[1:]) if t.startswith("-") else ("", t)
    k, _, m = body.partition("/")
    k = k.replace("*pi", r"\pi").replace("pi", r"\pi")
    return f"${sign}{k}$" if not m else f"${sign}\\frac{{{k}}}{{{m}}}$"


def _tabular(t: Table, labels: int, columns: Sequence[int], pi: bool) -> list[str]:
    """One ``tabular`` of ``t``: its first ``labels`` label columns and the value columns ``columns``
    (indices into ``t.columns``), the rows that have a value in one of them."""
    cols = [t.columns[k] for k in columns]
    out = [r"\begin{tabular}{" + "l" * labels + "r" * len(cols) + "}", r"\hline",
           " & ".join([_tex_text(s) for s in t.labels[:labels]] + [c[1] for c in cols]) + r" \\", r"\hline"]
    for lab, values in t.rows:
        if all(math.isnan(values[k]) for k in columns):  # no such quantity on this row
            continue
        cells = [_tex_text(s) for s in lab[:labels]] + [_tex_num(t, values[k], t.columns[k], pi) for k in columns]
        out.append(" & ".join(cells) + r" \\")
    return out + [r"\hline", r"\end{tabular}"]


def to_latex(t: Table, pi: bool = False) -> str:
    """A ``table`` environment (plain ``tabular`` and ``\\hline``; matrices need amsmath's bmatrix).

    The float holds several tabulars, so that a 7-joint arm fits the text width of an A4 article: the
    representation's columns (a PoE's omega, then its v; a GJD frame's rotation row by row, then its position); with mass
    properties each link's m and r, I's diagonal, I's products; the later ones labelled by the first
    one's i (row 0: the base body's)."""
    mass_heads = {c for c, _ in MASS_COLUMNS}
    kin = [k for k, c in enumerate(t.columns) if c[0] not in mass_heads]
    mass = [k for k, c in enumerate(t.columns) if c[0] in mass_heads]
    # a screw's omega then its v; a frame's rotation row by row, then its position: long decimals
    # (sqrt(2)/2 to 15 digits) six or twelve abreast overflow the page
    if len(kin) == 6:
        parts = [kin[:3], kin[3:]]
    elif len(kin) == 12:
        parts = [kin[0:3], kin[4:7], kin[8:11], kin[3::4]]
    else:
        parts = [kin]
    out = [r"\begin{table}[ht]", r"\centering", f"\\caption{{{_tex_text(t.title)}}}"]
    for k, part in enumerate(parts):
        out += ([] if k == 0 else ["", r"\medskip"]) + _tabular(t, len(t.labels) if k == 0 else 1, part, pi)
    if mass:  # m and r, I's diagonal, I's products: each part about as wide as the representation's table
        for part in (mass[:4], mass[4:7], mass[7:]):
            out += ["", r"\medskip", *_tabular(t, 1, part, pi)]
    for name, T in t.transforms:
        block = [_tex(s) for s in _block_text(t, T)] + ["0", "0", "0", "1"]
        rows = [" & ".join(block[4 * r:4 * r + 4]) for r in range(4)]
        # a word upright (\mathrm{base}), not a product of the variables b, a, s, e; M stays a symbol
        label = _tex_text(name) if len(name) == 1 else f"\\mathrm{{{_tex_text(name)}}}"
        out += ["", r"\smallskip", f"${label} = \\begin{{bmatrix}} " + r" \\ ".join(rows)
                + r" \end{bmatrix}$"]
    out.append(r"\end{table}")
    if len(t.labels) + len(kin) > 12 or mass:  # the GJD's 15 columns, the inertia's long numbers
        out.insert(1, r"\small")
    return "\n".join(out) + "\n"


def render_table(robot: Robot, rep: str, fmt: str, pi: bool = False, digits: int | str | None = None) -> str:
    """The robot in representation ``rep`` as ``fmt`` ('csv', 'markdown' or 'latex') text.

    ``digits``: None (default) the shortest decimals within the FK budget; N significant digits;
    'exact' every digit (reads back bit for bit). See the module.
    """
    t = with_precision(table_of(robot, rep), robot, digits)
    return {"csv": to_csv, "markdown": to_markdown, "latex": to_latex}[fmt](t, pi)
