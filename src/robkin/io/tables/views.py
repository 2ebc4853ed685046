"""Readable text of the table and result types: what ``str()`` of each shows, and what the CLI prints.

One layout per type, shared by ``str(table)``, ``robkin convert`` (through ``io.tables.blocks``),
``str(ik_result)`` and ``str(comparison)`` / ``robkin check``:

- ``table_blocks(table)``: a DHTable, MDHTable, HayatiTable, PoE or RPYTable as a table with one row per joint,
  plus its base / tool / M matrices;
- ``ik_result_blocks(result)``: one row per target (success, errors, q) or per solution;
- ``comparison_blocks(comparison)``: the joint-by-joint diagnosis of ``equivalence.compare``.

Blocks are printed by ``io.tables.show_blocks`` (rich on a terminal) or joined by ``blocks_text``.

Display rule of the representation tables (``table_blocks``, ``io.tables.blocks``): they are for reading,
so a value closer to 0 than ``DISPLAY_ZERO`` (an angle or a unitless entry, such as a rotation-matrix or
axis component, in radians / as is; a length relative to the robot's size) is shown as 0, and one note
line under the table says so. A URDF that writes pi/2 as 1.57079632679 describes a real 4.9e-12 rad
tilt, which conversions keep; printed as ``-4.89657e-12`` it reads as an error. Files (YAML, JSON, CSV,
Markdown, LaTeX, URDF, MJCF), ``to_dict()`` and JSON output are not display: they keep every digit.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence, Union, cast

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from ...equivalence.comparison import Comparison
    from ...kinematics.ik import IKResult
    from ...representations import DHTable, PoE, RPYTable
    from ...representations.link_table import LinkTable
    from ...robot import Joint

__all__ = ["Block", "DISPLAY_ZERO", "DISPLAY_NOTE", "MASS_HEADERS", "table_text", "table_blocks", "mass_blocks",
           "mass_frame", "frames_blocks", "solutions_block",
           "ik_result_blocks", "comparison_blocks", "blocks_text"]

#: Rows of a batch IK result shown by str(); a batch of 1e5 targets stays a screenful.
MAX_ROWS = 20

#: One piece of output: a table (title, headers, rows) or a line of text / a matrix block.
Block = Union[tuple[Union[str, None], Sequence[str], Sequence[Sequence[object]]], str]


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
        from .terminal import fmt_num

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


def _is_a(table: object, module: str, cls: str) -> bool:
    """``isinstance(table, robkin.representations.<module>.<cls>)`` without importing that module: a
    table of a class whose module is not loaded cannot exist (the representations are imported on
    first use, and printing a DH table should not import the four others)."""
    mod = sys.modules.get(f"robkin.representations.{module}")
    return mod is not None and isinstance(table, getattr(mod, cls))


def _robot_scale(table: "LinkTable | PoE | RPYTable") -> float:
    """``Robot.scale`` of the robot a table describes (1 for a bare LinkTable, which has no robot)."""
    if any(_is_a(table, m, c) for m, c in (("dh", "DHTable"), ("mdh", "MDHTable"), ("hayati", "HayatiTable"),
                                           ("poe", "PoE"), ("rpy_xyz", "RPYTable"))):
        return table.to_robot().scale  # type: ignore[union-attr]
    return 1.0


def _joint_cols(joints: Sequence["Joint"]) -> list[list[object]]:
    return [[str(i + 1), j.name, j.type + (" (flip)" if j.flip else "")] for i, j in enumerate(joints)]


def table_blocks(table: "LinkTable | PoE | RPYTable", title: str | None = None,
                 layout: str = "robkin", degrees: bool = False, scale: float | None = None) -> list[Block]:
    """A representation as tables and text lines (see the module docstring).

    ``layout='paper'`` puts a DH table in the conversion paper's n+1-row layout (row 0 is the fixed
    base row) when the base is one DH row. ``degrees`` shows the angle columns (alpha, theta, beta;
    roll, pitch, yaw) in degrees. ``scale`` is the robot's size (``Robot.scale``) for the display rule
    of lengths; by default the table's own robot's.
    """
    from ...representations.link_table import LinkTable, placement_notes
    from .terminal import matrix_text

    jc = _joint_cols(table.joints)
    unit = " (deg)" if degrees else ""
    shown = _Display(_robot_scale(table) if scale is None else scale)
    if isinstance(table, LinkTable):
        dh, hayati = _is_a(table, "dh", "DHTable"), _is_a(table, "hayati", "HayatiTable")
        standard = dh or hayati
        heads = ["i", "joint", "type", "a", "d", f"alpha{unit}", f"theta{unit}"] if standard else \
            ["i", "joint", "type", "a(i-1)", "d", f"alpha(i-1){unit}", f"theta{unit}"]
        if hayati:
            heads.append(f"beta{unit}")
        values = np.array(table.rows)
        base_row = cast("DHTable", table).base_row() if dh and layout == "paper" else None
        labels: list[list[object]] = jc
        if base_row is not None:
            values = np.vstack([base_row, values])
            labels = [["0", "(base)", "fixed"], *jc]
        values = shown.values(values, [0, 1])  # a, d are lengths; alpha, theta, beta angles
        if degrees:
            values[:, 2:] = np.degrees(values[:, 2:])
        out: list[Block] = [(title, heads, [c + list(r) for c, r in zip(labels, values)])]
        out.append("theta (revolute) and d (prismatic) are the values at q = 0; joint i adds q_i"
                   + (" (subtracts, if flipped)" if any(j.flip for j in table.joints) else "") + ".")
        if base_row is None:
            out.append(matrix_text(shown.matrix(table.base), "base"))
        out.append(matrix_text(shown.matrix(table.tool),
                               "tool (residual T_t)" if dh else "tool"))
        out.extend(f"note: {line}" for line in placement_notes(table))
        return out + mass_blocks(table, shown) + shown.note()
    if _is_a(table, "poe", "PoE"):
        poe = cast("PoE", table)
        heads = ["i", "joint", "type", "wx", "wy", "wz", "vx", "vy", "vz"]
        screws = shown.values(poe.screws, [3, 4, 5])  # omega is unitless, v a length
        return [(title, heads, [c + list(s) for c, s in zip(jc, screws)]),
                matrix_text(shown.matrix(poe.M), "M"), *mass_blocks(poe, shown), *shown.note()]
    if _is_a(table, "rpy_xyz", "RPYTable"):
        values = shown.values(cast("RPYTable", table).rows, [3, 4, 5])  # roll, pitch, yaw; x, y, z
        if degrees:
            values[:, :3] = np.degrees(values[:, :3])
        rpy_labels: list[list[object]] = [["0", "world->base", ""], *jc, [str(table.n + 1), "tool", ""]]
        return [(title, ["row", "frame", "type", f"roll{unit}", f"pitch{unit}", f"yaw{unit}", "x", "y", "z"],
                 [lab + list(r) for lab, r in zip(rpy_labels, values)]), *mass_blocks(table, shown),
                *shown.note()]
    raise TypeError(f"no table layout for {type(table).__name__}")


#: Headers of the mass-property columns (units: kg, the robot's length unit (normally m), kg m^2).
MASS_HEADERS = ("m (kg)", "rx (m)", "ry (m)", "rz (m)", "Ixx (kg m^2)", "Iyy (kg m^2)", "Izz (kg m^2)",
                "Ixy (kg m^2)", "Iyz (kg m^2)", "Ixz (kg m^2)")


def mass_frame(table: object) -> str:
    """The frame a table's mass properties are in, as the line under them says it."""
    if _is_a(table, "mdh", "MDHTable"):
        return "link frame {i} (on joint i's axis, where link i starts; Craig)"
    if _is_a(table, "rpy_xyz", "RPYTable"):
        return "joint i's frame (the frame row i leads to, which joint i moves)"
    if _is_a(table, "poe", "PoE"):
        return ("the robot base frame at q = 0" if cast("PoE", table).frame == "space"
                else "the home tool frame M")
    return "link frame {i} (after joint i, on axis i+1)"


def mass_blocks(table: "LinkTable | PoE | RPYTable", shown: _Display) -> list[Block]:
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
    from .terminal import matrix_text

    shown = _Display(scale)
    return [*(matrix_text(shown.matrix(F), label) for F, label in zip(frames, labels)), *shown.note()]


def table_text(table: "LinkTable | PoE | RPYTable") -> str:
    """``str()`` of a table: its blocks as plain text, titled with the representation's name."""
    from ..documents.reader import section_key
    from .terminal import FORMATS

    return blocks_text(table_blocks(table, FORMATS[section_key(table).replace("_", "-")]))


def solutions_block(solutions: np.ndarray, method: str, names: Sequence[str]) -> Block:
    """IK solutions (S, n) of one target as a table, one row per solution (as ``robkin ik`` prints)."""
    rows = [[str(i + 1), *s] for i, s in enumerate(solutions)]
    return (f"IK solutions ({method}, nearest to q0 first)", ["#", *names], rows)


def ik_result_blocks(result: "IKResult", names: Sequence[str] | None = None) -> list[Block]:
    """An IK result: with ``solutions`` of one target, one row per solution; otherwise one row per
    target with its success, errors and q (the best configuration found where it failed)."""
    q = np.asarray(result.q, dtype=float)
    n = q.shape[-1]
    names = list(names) if names is not None else [f"q{i + 1}" for i in range(n)]
    if q.ndim == 1 and isinstance(result.solutions, np.ndarray) and len(result.solutions):
        return [solutions_block(result.solutions, result.method, names)]
    Q = q.reshape(-1, n)
    success = np.broadcast_to(result.success, Q.shape[:1])
    pos = np.broadcast_to(result.position_error, Q.shape[:1])
    rot = np.broadcast_to(result.orientation_error, Q.shape[:1])
    messages = [result.message] * len(Q) if isinstance(result.message, str) else list(result.message)
    shown = range(min(len(Q), MAX_ROWS))
    rows = [[str(i + 1), "yes" if success[i] else "no", float(pos[i]), float(rot[i]), *Q[i]] for i in shown]
    out: list[Block] = [(f"IK ({result.method}): {int(np.sum(success))} of {len(Q)} reached",
                         ["#", "success", "position error", "orientation error", *names], rows)]
    if len(Q) > MAX_ROWS:
        out.append(f"... {len(Q) - MAX_ROWS} more targets (the arrays of the result hold them all)")
    out += [f"target {i + 1}: {messages[i]}" for i in shown if messages[i]]
    return out


def comparison_blocks(c: "Comparison", title: str | None = None) -> list[Block]:
    """The diagnosis of ``equivalence.compare``: per-joint table, tool, world, FK difference, verdict."""
    rows = [[str(j.index + 1), j.name_a, j.name_b, j.type_a if j.type_a == j.type_b else f"{j.type_a}/{j.type_b}",
             j.status, "-" if j.sign < 0 else "+", j.offset, j.detail] for j in c.joints]
    title = title or f"A ({c.n_a} joints) vs B ({c.n_b} joints)"
    out: list[Block] = []
    if c.n_a != c.n_b:  # the answer first: no joint-by-joint detail changes it
        out.append(f"verdict: {c.verdict()}")
    out += [(title, ["joint", "A", "B", "type", "status", "sign", "offset", "how"], rows),
            f"tool:  {c.tool}", f"world: {c.world}"]
    if math.isfinite(c.max_fk_error):
        what = "under the joint mapping" if c.equivalent and not c.same else "at the same q"
        out.append(f"largest FK difference at 64 random q {what}: {c.max_fk_error:.3g} (relative to robot size)")
    out += [f"note: {note}" for note in c.notes]
    if c.n_a == c.n_b:
        out.append(f"verdict: {c.verdict()}")
    return out


def blocks_text(items: Sequence[Block]) -> str:
    """Blocks as plain text, one after the other."""
    from .terminal import text_table

    return "\n".join(b if isinstance(b, str) else text_table(b[1], b[2], b[0]) for b in items)
