"""Readable text of the representation tables: what ``str()`` of a table shows, and what the CLI prints.

One layout per registered layout family (``robkin.representations.registry``), shared by
``str(table)`` (through the representations' facade ``robkin.representations.presentation``) and
``robkin convert`` (through ``io.tables.terminal.blocks``):

- ``table_blocks(table)``: a table (DHTable, MDHTable, HayatiTable, PoE, RPYTable, or any registered
  one) with one row per joint, plus its base / tool / M matrices and its mass properties;
- ``frames_blocks``: the GJD's frames.

The IK result and the equivalence comparison are laid out by their own layers (``kinematics.ik_text``,
``equivalence.report``) with the generic blocks of ``io.tables.text``.

Display rule of the representation tables (``table_blocks``, ``io.tables.terminal.blocks``): they are for reading,
so a value closer to 0 than ``DISPLAY_ZERO`` (an angle or a unitless entry, such as a rotation-matrix or
axis component, in radians / as is; a length relative to the robot's size) is shown as 0, and one note
line under the table says so. A URDF that writes pi/2 as 1.57079632679 describes a real 4.9e-12 rad
tilt, which conversions keep; printed as ``-4.89657e-12`` it reads as an error. Files (YAML, JSON, CSV,
Markdown, LaTeX, URDF, MJCF), ``to_dict()`` and JSON output are not display: they keep every digit.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from ...representations.registry import Column, Representation, of_table
from .text import Block, blocks_text, fmt_num, matrix_text

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Joint

__all__ = ["Block", "DISPLAY_ZERO", "DISPLAY_NOTE", "MASS_HEADERS", "table_text", "table_blocks", "mass_blocks",
           "mass_frame", "frames_blocks", "blocks_text"]

#: Values closer to 0 than this (radians, unitless, or times the robot's size for lengths) are shown as
#: 0 in the text tables. 1e-9: far above the noise of decimals such as 1.57079632679 for pi/2 (5e-12)
#: and of the frame algebra (~1e-15), far below any real angle or offset a table would be read for
#: (a 1e-9 rad tilt moves a 1 m arm by 1 nm); the exact values stay in every file written.
DISPLAY_ZERO = 1e-9
#: The note printed under a table in which the display rule hid a value.
DISPLAY_NOTE = ("note: values closer to 0 than 1e-9 (angles in rad; lengths times the robot's "
                "size) are shown as 0; files and JSON output keep full precision")


@dataclass
class _Display:
    """The display rule for one table: zeroes what it hides, remembers whether it hid anything shown."""

    scale: float
    hid: bool = False

    def values(self, values: np.ndarray, length_cols: Sequence[int]) -> np.ndarray:
        """``values`` (..., k) with the entries below the threshold of their column set to 0."""
        v = np.array(values, dtype=float)
        limit = np.full(v.shape[-1], DISPLAY_ZERO)
        limit[list(length_cols)] = DISPLAY_ZERO * self.scale
        small = (np.abs(v) < limit) & (v != 0)
        # a value fmt_num prints as 0 anyway is no news: only values that would show count for the note
        self.hid |= any(fmt_num(x) != "0" for x in v[small])
        v[small] = 0.0
        return v

    def matrix(self, T: np.ndarray) -> np.ndarray:
        """A 4x4 pose: rotation entries are unitless, the translation column is a length."""
        return self.values(T, [3])

    def note(self) -> list[str]:
        return [DISPLAY_NOTE] if self.hid else []


def _robot_scale(table: Any) -> float:
    """``Robot.scale`` of the robot a table describes (1 for a table of no registered representation,
    such as a bare LinkTable, which has no robot)."""
    try:
        of_table(table)
    except TypeError:
        return 1.0
    return table.to_robot().scale


def _joint_cols(joints: Sequence["Joint"]) -> list[list[object]]:
    return [[str(i + 1), j.name, j.type + (" (flip)" if j.flip else "")] for i, j in enumerate(joints)]


def _columns(rep: Representation | None, table: Any) -> list[Column]:
    """The table's columns: its representation's, or (a bare LinkTable) its class's, as DH's."""
    if rep is not None:
        return list(rep.columns)
    from ...representations.registry import by_name

    mdh = by_name("mdh").columns  # the old layout of a bare LinkTable: modified DH's headers
    return [*mdh, *(Column(c, c, c, "angle") for c in table.COLUMNS[len(mdh):])]


def table_blocks(table: Any, title: str | None = None,
                 layout: str = "robkin", degrees: bool = False, scale: float | None = None) -> list[Block]:
    """A representation as tables and text lines (see the module docstring).

    ``layout='paper'`` puts a DH table in the conversion paper's n+1-row layout (row 0 is the fixed
    base row) when the base is one DH row. ``degrees`` shows the angle columns (alpha, theta, beta;
    roll, pitch, yaw) in degrees. ``scale`` is the robot's size (``Robot.scale``) for the display rule
    of lengths; by default the table's own robot's.
    """
    from ...representations.link_table import LinkTable, placement_notes

    try:
        rep: Representation | None = of_table(table)
    except TypeError:
        rep = None
    if rep is None and not isinstance(table, LinkTable):
        raise TypeError(f"no table layout for {type(table).__name__}")
    jc = _joint_cols(table.joints)
    unit = " (deg)" if degrees else ""
    shown = _Display(_robot_scale(table) if scale is None else scale)
    cols = _columns(rep, table)
    heads = [c.header + (unit if c.angle else "") for c in cols]
    lengths = [k for k, c in enumerate(cols) if c.kind == "length"]
    angles = [k for k, c in enumerate(cols) if c.angle]
    if rep is None or rep.layout == "link-table":
        values = np.array(table.rows)
        base_row = table.base_row() if rep is not None and rep.paper_layout and layout == "paper" else None
        labels: list[list[object]] = jc
        if base_row is not None:
            values = np.vstack([base_row, values])
            labels = [["0", "(base)", "fixed"], *jc]
        values = shown.values(values, lengths)
        if degrees:
            values[:, angles] = np.degrees(values[:, angles])
        out: list[Block] = [(title, ["i", "joint", "type", *heads], [c + list(r) for c, r in zip(labels, values)])]
        out.append("theta (revolute) and d (prismatic) are the values at q = 0; joint i adds q_i"
                   + (" (subtracts, if flipped)" if any(j.flip for j in table.joints) else "") + ".")
        if base_row is None:
            out.append(matrix_text(shown.matrix(table.base), "base"))
        out.append(matrix_text(shown.matrix(table.tool), rep.tool_label if rep is not None else "tool"))
        out.extend(f"note: {line}" for line in placement_notes(table))
        return out + mass_blocks(table, shown) + shown.note()
    if rep.layout == "screws":
        screws = shown.values(table.screws, lengths)  # omega is unitless, v a length
        return [(title, ["i", "joint", "type", *heads], [c + list(s) for c, s in zip(jc, screws)]),
                matrix_text(shown.matrix(table.M), "M"), *mass_blocks(table, shown), *shown.note()]
    if rep.layout == "rpy":
        values = shown.values(table.rows, lengths)
        if degrees:
            values[:, angles] = np.degrees(values[:, angles])
        rpy_labels: list[list[object]] = [["0", "world->base", ""], *jc, [str(table.n + 1), "tool", ""]]
        return [(title, ["row", "frame", "type", *heads], [lab + list(r) for lab, r in zip(rpy_labels, values)]),
                *mass_blocks(table, shown), *shown.note()]
    raise TypeError(f"no table layout for {type(table).__name__}")  # pragma: no cover - layouts are checked


#: Headers of the mass-property columns (units: kg, the robot's length unit (normally m), kg m^2).
MASS_HEADERS = ("m (kg)", "rx (m)", "ry (m)", "rz (m)", "Ixx (kg m^2)", "Iyy (kg m^2)", "Izz (kg m^2)",
                "Ixy (kg m^2)", "Iyz (kg m^2)", "Ixz (kg m^2)")


def mass_frame(table: object) -> str:
    """The frame a table's mass properties are in, as the line under them says it."""
    try:
        return of_table(table).mass_frame
    except TypeError:
        return "link frame {i} (after joint i, on axis i+1)"


def mass_blocks(table: Any, shown: _Display) -> list[Block]:
    """The table's mass properties (``masses``), one row per link, with the frame they are in; none
    when the table has none. The display rule hides centres of mass below DISPLAY_ZERO times the
    robot's size and inertia entries below DISPLAY_ZERO times the largest one."""
    from ...representations.mass_rows import six_from_tensor

    masses = table.masses
    if masses is None:
        return []
    mass, com, inertia = masses.bodies()  # bodies 0..n; body 0 shown only when known
    six = six_from_tensor(inertia)
    values = np.column_stack([mass, shown.values(com, [0, 1, 2]), six])
    small = (np.abs(six) < DISPLAY_ZERO * float(np.abs(six).max())) & (six != 0)
    values[:, 4:][small] = 0.0
    labels = [["0", "(base)"]] + [[str(i + 1), j.name] for i, j in enumerate(table.joints)]
    rows = [lab + list(v) for lab, v in zip(labels, values)][0 if masses.base is not None else 1:]
    return [("mass properties of each link (everything fixed to it merged in)", ["i", "joint", *MASS_HEADERS],
             rows),
            f"r and I in {mass_frame(table)}; I about the centre of mass (products as in URDF: Ixy = -sum m x y)"
            + ("; the base's in frame 0." if masses.base is not None else ".")]


def frames_blocks(frames: np.ndarray, labels: Sequence[str], scale: float) -> list[Block]:
    """GJD frames (k, 4, 4) as labelled matrix blocks, with the display rule of the tables."""
    shown = _Display(scale)
    return [*(matrix_text(shown.matrix(F), label) for F, label in zip(frames, labels)), *shown.note()]


def table_text(table: Any) -> str:
    """``str()`` of a table: its blocks as plain text, titled with the representation's description."""
    from ...representations.registry import by_section

    try:
        rep = of_table(table)
    except TypeError:  # a bare LinkTable: titled by its SECTION
        rep = by_section(table.SECTION)
    return blocks_text(table_blocks(table, rep.description))
