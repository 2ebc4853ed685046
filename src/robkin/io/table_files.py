"""Tables for papers and spreadsheets: a representation as CSV, Markdown or LaTeX, full precision.

Every number is written so that it reads back to the same float (``repr``), or, with ``pi=True``, as
an exact multiple of pi (``-pi/2``, ``3*pi/4``) wherever an angle *is* that float (evaluating the text
``k*pi/m`` gives back the very same number; 1.57079632679 typed into a URDF is not pi/2 and stays a
decimal). Lengths are in the robot's unit (normally metres), angles in radians.

Layout (the same content in each format)
    the joint rows: index, joint name, type, then the representation's columns (DH: a, d, alpha,
    theta; MDH: a(i-1), d, alpha(i-1), theta; PoE: wx, wy, wz, vx, vy, vz; RPY-XYZ: n + 2 rows of
    roll, pitch, yaw, x, y, z; GJD: the 3 x 4 block of each frame); then the fixed transforms that
    complete the table (DH/MDH/Hayati: base and tool; PoE: M), each as its 3 x 4 block [R | p]
    row-major. CSV puts those after an empty line, in rows ``name,m11,m12,m13,m14,m21,...,m34``.

Mass properties
    When the robot has them, each joint row ends with ten more columns: ``m (kg)``, ``rx (m)``,
    ``ry (m)``, ``rz (m)``, ``Ixx (kg m^2)``, ``Iyy``, ``Izz``, ``Ixy``, ``Iyz``, ``Ixz`` (the same
    unit): link i's mass, centre of mass and inertia about it, in the table's own link frame i
    (``robkin.representations.mass_rows``). RPY-XYZ's world and tool rows leave them empty.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ..errors import InputError
from ..robot import Robot
from .float_text import float_text as _num

if TYPE_CHECKING:  # pragma: no cover
    from ..representations.link_table import LinkTable
    from ..representations.mass_rows import MassRows

__all__ = ["TABLE_FORMATS", "TABLE_EXTENSIONS", "TABLE_REPRESENTATIONS", "Table", "table_of", "render_table",
           "pi_text"]

TABLE_FORMATS = ("csv", "markdown", "latex")
TABLE_EXTENSIONS = {"csv": ".csv", "markdown": ".md", "latex": ".tex"}
TABLE_REPRESENTATIONS = ("dh", "mdh", "hayati", "poe", "poe-body", "rpy-xyz", "gjd")
#: Denominators tried for multiples of pi: every angle a table of a real robot has in closed form
#: (pi/2, pi/3, pi/4, pi/6, pi/12, ...). Numerators up to 2 * denominator (one full turn).
PI_DENOMINATORS = (1, 2, 3, 4, 6, 8, 12)
_BLOCK = [f"m{r}{c}" for r in (1, 2, 3) for c in (1, 2, 3, 4)]


@dataclass
class Table:
    """One representation as a table: columns (name, LaTeX header, whether it is an angle), rows
    (labels then numbers), and the fixed transforms (name, (4, 4)) that complete it."""

    title: str
    labels: Sequence[str]
    columns: Sequence[tuple[str, str, bool]]
    rows: list[tuple[list[str], list[float]]]
    transforms: list[tuple[str, np.ndarray]] = field(default_factory=list)


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


def _cell(x: float, angle: bool, pi: bool) -> str:
    if math.isnan(x):  # a row without this column's quantity (RPY-XYZ's world and tool rows: no mass)
        return ""
    if pi and angle:
        t = pi_text(float(x))
        if t is not None:
            return t
    return _num(x)


def _joint_labels(robot: Robot) -> list[list[str]]:
    return [[str(i + 1), j.name, j.type + (" (flip)" if j.flip else "")] for i, j in enumerate(robot.joints)]


def _link_table(robot: Robot, rep: str) -> "LinkTable":
    from ..representations import dh_from_robot, hayati_from_robot, mdh_from_robot

    return {"dh": dh_from_robot, "mdh": mdh_from_robot, "hayati": hayati_from_robot}[rep](robot)


def table_of(robot: Robot, rep: str) -> Table:
    """The robot in representation ``rep`` (one of TABLE_REPRESENTATIONS) as a ``Table``."""
    from ..representations import poe_from_robot, rpy_from_robot

    name = robot.name or "robot"
    jl = _joint_labels(robot)
    if rep in ("dh", "mdh", "hayati"):
        t = _link_table(robot, rep)
        prev = rep == "mdh"  # Craig's a and alpha belong to the previous link
        cols = [("a(i-1)" if prev else "a", "$a_{i-1}$" if prev else "$a_i$", False), ("d", "$d_i$", False),
                ("alpha(i-1)" if prev else "alpha", r"$\alpha_{i-1}$" if prev else r"$\alpha_i$", True),
                ("theta", r"$\theta_i$", True)]
        if rep == "hayati":
            cols.append(("beta", r"$\beta_i$", True))
        title = {"dh": "standard DH", "mdh": "modified (Craig) DH", "hayati": "Hayati"}[rep]
        return with_mass_columns(Table(f"{name}: {title}", ["i", "joint", "type"], cols,
                                       [(lab, list(map(float, r))) for lab, r in zip(jl, np.asarray(t.rows))],
                                       [("base", t.base), ("tool", t.tool)]), t.masses)
    if rep in ("poe", "poe-body"):
        p = poe_from_robot(robot, "space" if rep == "poe" else "body")
        cols = [(c, f"${c[0]}_{c[1]}$" if c[0] == "v" else fr"$\omega_{c[1]}$", False)
                for c in ("wx", "wy", "wz", "vx", "vy", "vz")]
        return with_mass_columns(Table(f"{name}: PoE ({'space' if rep == 'poe' else 'body'} frame)",
                                       ["i", "joint", "type"], cols,
                                       [(lab, list(map(float, s))) for lab, s in zip(jl, p.screws)], [("M", p.M)]),
                                 p.masses)
    if rep == "rpy-xyz":
        rpy = rpy_from_robot(robot)
        labels = [["0", "world->base", ""]] + jl + [[str(robot.n + 1), "tool", ""]]
        cols = [("roll", "roll", True), ("pitch", "pitch", True), ("yaw", "yaw", True),
                ("x", "$x$", False), ("y", "$y$", False), ("z", "$z$", False)]
        return with_mass_columns(Table(f"{name}: RPY-XYZ", ["row", "frame", "type"], cols,
                                       [(lab, list(map(float, r))) for lab, r in zip(labels, rpy.rows)]),
                                 rpy.masses, first=1)
    if rep == "gjd":
        labels = jl + [[str(robot.n + 1), "tool", ""]]
        cols = [(m, f"${m[0]}_{{{m[1:]}}}$", False) for m in _BLOCK]
        return Table(f"{name}: Global Joint Description (frames at q = 0)", ["i", "frame", "type"], cols,
                     [(lab, list(map(float, F[:3].ravel()))) for lab, F in zip(labels, robot.frames)])
    raise InputError(f"'{rep}' has no table form; tables exist for {', '.join(TABLE_REPRESENTATIONS)}")


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
    from ..representations.mass_rows import six_from_tensor

    mass, com, inertia = masses.bodies()  # bodies 0..n: body 0 on the row before the first link's, if any
    values = np.column_stack([mass, com, six_from_tensor(inertia)])
    rows = []
    for k, (lab, row) in enumerate(t.rows):
        known = 0 <= k - first < masses.n or (k == first - 1 and masses.base is not None)
        extra = values[k - first + 1] if known else np.full(len(MASS_COLUMNS), np.nan)
        rows.append((lab, row + [float(v) for v in extra]))
    return Table(t.title, t.labels, [*t.columns, *((c, tex, False) for c, tex in MASS_COLUMNS)], rows,
                 t.transforms)


def to_csv(t: Table, pi: bool = False) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(list(t.labels) + [c[0] for c in t.columns])
    for lab, values in t.rows:
        w.writerow(lab + [_cell(v, c[2], pi) for v, c in zip(values, t.columns)])
    if t.transforms:
        w.writerow([])
        w.writerow(["transform"] + _BLOCK)
        for name, T in t.transforms:
            w.writerow([name] + [_num(v) for v in np.asarray(T)[:3].ravel()])
    return buf.getvalue()


def _md_escape(s: str) -> str:
    return s.replace("\\", "\\\\").replace("|", "\\|")


def to_markdown(t: Table, pi: bool = False) -> str:
    heads = list(t.labels) + [c[0] for c in t.columns]
    align = [":--"] * len(t.labels) + ["--:"] * len(t.columns)
    out = [f"**{_md_escape(t.title)}**", "", "| " + " | ".join(heads) + " |", "|" + "|".join(align) + "|"]
    for lab, values in t.rows:
        cells = [_md_escape(s) for s in lab] + [_cell(v, c[2], pi) for v, c in zip(values, t.columns)]
        out.append("| " + " | ".join(cells) + " |")
    for name, T in t.transforms:
        out += ["", f"{name} [R | p]:", "", "| | 1 | 2 | 3 | 4 |", "|:--|--:|--:|--:|--:|"]
        out += [f"| {r + 1} | " + " | ".join(_num(v) for v in np.asarray(T)[r]) + " |" for r in range(3)]
    return "\n".join(out) + "\n"


_TEX = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_",
        "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}


def _tex_text(s: str) -> str:
    return "".join(_TEX.get(c, c) for c in s)


def _tex_num(x: float, angle: bool, pi: bool) -> str:
    if math.isnan(x):  # no quantity in this row (see _cell)
        return ""
    t = pi_text(float(x)) if pi and angle else None
    if t is None:
        return f"${_tex(_num(x))}$"
    sign, body = ("-", t[1:]) if t.startswith("-") else ("", t)
    k, _, m = body.partition("/")
    k = k.replace("*pi", r"\pi").replace("pi", r"\pi")
    return f"${sign}{k}$" if not m else f"${sign}\\frac{{{k}}}{{{m}}}$"


def to_latex(t: Table, pi: bool = False) -> str:
    """A ``table`` environment (plain ``tabular`` and ``\\hline``; matrices need amsmath's bmatrix)."""
    ncol = len(t.labels) + len(t.columns)
    heads = [_tex_text(s) for s in t.labels] + [c[1] for c in t.columns]
    out = [r"\begin{table}[ht]", r"\centering", f"\\caption{{{_tex_text(t.title)}}}",
           r"\begin{tabular}{" + "l" * len(t.labels) + "r" * len(t.columns) + "}", r"\hline",
           " & ".join(heads) + r" \\", r"\hline"]
    for lab, values in t.rows:
        cells = [_tex_text(s) for s in lab] + [_tex_num(v, c[2], pi) for v, c in zip(values, t.columns)]
        out.append(" & ".join(cells) + r" \\")
    out += [r"\hline", r"\end{tabular}"]
    for name, T in t.transforms:
        rows = [" & ".join(_tex(_num(v)) for v in np.asarray(T)[r]) for r in range(4)]
        out += ["", r"\smallskip", f"${_tex_text(name)} = \\begin{{bmatrix}} " + r" \\ ".join(rows)
                + r" \end{bmatrix}$"]
    out.append(r"\end{table}")
    if ncol > 12:  # the GJD's 15 columns: let the float be as wide as the page allows
        out.insert(1, r"\small")
    return "\n".join(out) + "\n"


def render_table(robot: Robot, rep: str, fmt: str, pi: bool = False) -> str:
    """The robot in representation ``rep`` as ``fmt`` ('csv', 'markdown' or 'latex') text."""
    t = table_of(robot, rep)
    return {"csv": to_csv, "markdown": to_markdown, "latex": to_latex}[fmt](t, pi)
