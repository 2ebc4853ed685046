"""Are two descriptions the same robot? If not, which joint differs first, and how.

Two robots A and B (FK in their base frames) are *the same robot* iff T_A(q) = T_B(q) for every q. With
space-frame screws S_i and home tool poses M (T(q) = exp([S_1] q_1) ... exp([S_n] q_n) M), the
derivative at q = 0 gives [S_i] M, so this holds iff S_i^A = S_i^B for every i and M_A = M_B.

They are *the same mechanism under a joint mapping* iff T_B(q) = T_A(s * q + delta) for signs
s_i = +-1 and zero offsets delta_i (q_A = s q_B + delta). Writing exp([S] (s q + d)) =
exp([S] d) exp([s S] q) and moving the fixed factors to the right,

    S_i^B = s_i Ad(G_{i-1}) S_i^A,   M_B = G_n M_A,   G_i = G_{i-1} exp([S_i^A] delta_i), G_0 = I.

So the comparison walks the joints in order: joint i's axis in B must be joint i's axis in A moved by
the offsets of the joints before it, traversed in the same (s = +1) or opposite (s = -1) direction.
A joint's offset stays open until a later axis (or the tool) depends on it (a non-zero Lie bracket);
then it is solved for: one rotation in closed form, slides by linear least squares (several slides
may stay partly open, with the constraint that later changes keep the axes already placed), a
rotation together with slides by a small nonlinear solve. The offset of a joint coaxial with a later
one of the same type is carried by the later joint. Where a rotation by pi lets both signs fit, a
depth-first search tries the preferred mapping (no offset, sign +1) first and backtracks. The first
joint whose axis cannot be matched is reported with how it differs: type, axis direction (angle), or
axis position (distance between the lines; revolute joints only, a prismatic joint is a direction).

When no mapping exists, the walk's greed can name the wrong joint: a zero offset of joint k-1 may carry
a tilted axis k into place and leave every later axis out of place. ``equivalence.attribution`` then
weighs the walk's explanation against the axes as they are, and names the first joint whose axis line
differs when that leaves less unexplained (issue 32).

A rotation of the base about joint 1's axis cannot be told from a zero offset of joint 1 (FK is in
the base frame), and is reported as the latter; a half turn there gets a note naming the base frame
(a ROS URDF's ``base_link`` against a vendor table's ``base``) and ``base_link=``.

Past the first joint that cannot be matched the comparison goes on parameter by parameter
(``equivalence.params``): both robots written as the same kind of table by the same frame rules, each
row that differs names its parameters with both values ('a2 -0.6127 vs -0.612 m'); a later joint whose
row matches is 'aligned'.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .attribution import attribute
from .params import ParameterDifference, parameter_differences
from .walk import Walk, pose_difference
from ..robot import Robot
from ..samples import unit_sample

__all__ = ["JointMatch", "Comparison", "compare", "DEFAULT_TOL"]

#: Default relative tolerance: rotations (dimensionless) and lengths divided by the robot's size. 1e-6
#: accepts descriptions typed with 7 significant digits (vendor DH tables, URDFs rounded to 1e-6 m)
#: while any real difference of a joint (a millimetre on a metre arm is 1e-3) is far above it.
DEFAULT_TOL = 1e-6


@dataclass(frozen=True)
class JointMatch:
    """How joint i of B corresponds to joint i of A: q_A = sign * q_B + offset, or why it does not."""

    index: int
    name_a: str
    name_b: str
    type_a: str
    type_b: str
    status: str  # same | sign | offset | sign+offset | differs | unchecked (| aligned: see compare)
    sign: int = 1
    offset: float = 0.0
    detail: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {"joint": self.index + 1, "name_a": self.name_a, "name_b": self.name_b, "type_a": self.type_a,
                "type_b": self.type_b, "status": self.status, "sign": self.sign, "offset": self.offset,
                "detail": self.detail}


@dataclass(frozen=True)
class Comparison:
    """Result of ``compare``: the verdict, the per-joint diagnosis and the measured differences.

    ``same``: FK equal at every q (with the same q). ``equivalent``: the same mechanism, with the joint
    mapping q_A = sign * q_B + offset given per joint. ``first_difference``: one line, None if same.
    """

    same: bool
    equivalent: bool
    n_a: int
    n_b: int
    joints: tuple[JointMatch, ...]
    first_difference: str | None
    tool: str
    world: str
    max_fk_error: float
    tol: float
    notes: tuple[str, ...] = field(default_factory=tuple)
    #: the table values that differ (both robots written as ``table`` by the same rules); see
    #: ``equivalence.params``. Empty when the robots are the same or their joint counts differ.
    parameters: tuple[ParameterDifference, ...] = field(default_factory=tuple)
    table: str = ""

    def verdict(self) -> str:
        if self.same:
            return "same robot: the tool pose is the same at every q"
        if self.equivalent:
            return ("same mechanism, different joint convention: q_A = sign * q_B + offset per joint "
                    "(see the table)")
        return f"different robots: {self.first_difference}"

    def __str__(self) -> str:
        """The joint-by-joint diagnosis as ``robkin check`` prints it."""
        from ..io.tables.text import blocks_text
        from .report import comparison_blocks

        return blocks_text(comparison_blocks(self))

    def __repr__(self) -> str:
        return (f"Comparison(same={self.same}, equivalent={self.equivalent}, "
                f"first_difference={self.first_difference!r})")

    def to_dict(self) -> dict[str, Any]:
        return {"same": self.same, "equivalent": self.equivalent, "verdict": self.verdict(),
                "first_difference": self.first_difference, "joints": [j.to_dict() for j in self.joints],
                "tool": self.tool, "world": self.world,
                "max_fk_error": self.max_fk_error if math.isfinite(self.max_fk_error) else None, "tol": self.tol,
                "n_a": self.n_a, "n_b": self.n_b, "notes": list(self.notes),
                "table": self.table or None, "parameters": [d.to_dict() for d in self.parameters]}


# --------------------------------------------------------------------------------------- compare
def compare(a: Robot, b: Robot, tol: float = DEFAULT_TOL, samples: int = 64) -> Comparison:
    """Compare robot A with robot B joint by joint (see the module docstring for the method).

    Parameters
    ----------
    a, b : Robot
    tol : float
        Relative tolerance: on rotations and axis directions (rad), and on lengths divided by the
        larger robot size.
    samples : int
        Random configurations at which the verdict is double-checked by FK (reported as max_fk_error,
        relative to the robot size).
    """
    scale = max(a.scale, b.scale)
    if scale < 1e-100:
        # Robot.scale can return rounding noise (seen: 1e-131) when every axis and frame sits at
        # the origin; such a robot has no size, and dividing by the noise would amplify it to 1e99
        scale = 1.0
    notes: list[str] = []
    world_d, world_a = pose_difference(a.world, b.world)
    world = ("same" if world_d <= tol * scale and world_a <= tol else
             f"differs (position by {world_d:.4g} m, rotation by {math.degrees(world_a):.4g} deg); "
             "it places the base in the world and is not part of FK")
    n = min(a.n, b.n)
    joints: list[JointMatch] = []
    first: str | None = None
    if a.n != b.n:
        first = f"joint counts differ: A has {a.n}, B has {b.n}"
    SA, SB = a.screws(), b.screws()
    walk = Walk(a, b, SA, SB, scale, tol)
    walked = walk.run(n)
    result = attribute(a, b, walked, scale, tol)  # the joint whose axis moved, not an offset before it
    signs, offsets, matched = result.signs, result.offsets, result.matched
    joints = [JointMatch(k, a.joints[k].name, b.joints[k].name, a.joints[k].type, b.joints[k].type, "same")
              for k in range(matched)]
    if result.failure is not None and matched < n:
        ja, jb = a.joints[matched], b.joints[matched]
        joints.append(JointMatch(matched, ja.name, jb.name, ja.type, jb.type, "differs", detail=result.failure))
        first = first or f"joint {matched + 1} ('{ja.name}' / '{jb.name}'): {result.failure}"
    tool = ("not compared (the joint counts differ)" if a.n != b.n and matched == n
            else "not compared (a joint differs before it)")
    all_joints = matched == n and a.n == b.n
    if all_joints:
        tool = result.tool
        if tool != "same":
            first = first or f"tool: home pose {tool[len('differs: '):]} (every joint axis matches)"
    # per-joint status from the mapping found so far
    tol_off = [tol if a.joints[i].revolute else tol * scale for i in range(n)]
    for k in range(matched):
        jm = joints[k]
        flipped = signs[k] == -1
        shifted = abs(offsets[k]) > tol_off[k]
        status = "sign+offset" if flipped and shifted else "sign" if flipped else "offset" if shifted else "same"
        parts = []
        if flipped:
            parts.append("positive direction reversed")
        if shifted:
            unit = "rad" if a.joints[k].revolute else "m"
            parts.append(f"zero offset {offsets[k]:+.6g} {unit}")
        joints[k] = JointMatch(jm.index, jm.name_a, jm.name_b, jm.type_a, jm.type_b, status, int(signs[k]),
                               float(offsets[k]) if shifted else 0.0, "; ".join(parts))
    mapped = all_joints and tool == "same"
    same = mapped and all(j.status == "same" for j in joints)
    kind: str = ""
    params: list[ParameterDifference] = []
    if a.n == b.n and not mapped and a.types == b.types:
        # past the first difference (a joint mapping, where there is one, explains every row instead): both robots as the same kind of table, row against row
        kind, params = parameter_differences(a, b, scale, tol)
        for k in range(min(matched, len(joints))):  # axes that match, with a row that does not
            rows = "; ".join(d.text() for d in params if d.joint == k + 1)
            if rows:
                jm = joints[k]
                joints[k] = JointMatch(jm.index, jm.name_a, jm.name_b, jm.type_a, jm.type_b, jm.status, jm.sign,
                                       jm.offset, "; ".join(filter(None, [jm.detail, f"{kind}: {rows} (axis {k + 1} "
                                                                          "matches; the axes after it move)"])))
        if len(joints) > matched and params:
            diff = joints[matched]
            rows = "; ".join(d.text() for d in params if d.joint == matched + 1)
            joints[matched] = JointMatch(diff.index, diff.name_a, diff.name_b, diff.type_a, diff.type_b, diff.status,
                                         detail=diff.detail + (f" ({kind}: {rows})" if rows else ""))
    for k in range(len(joints), n):
        ja, jb = a.joints[k], b.joints[k]
        if not kind:
            joints.append(JointMatch(k, ja.name, jb.name, ja.type, jb.type, "unchecked"))
            continue
        texts = [d.text() for d in params if d.joint == k + 1]
        joints.append(JointMatch(k, ja.name, jb.name, ja.type, jb.type, "differs" if texts else "aligned",
                                 detail=f"{kind}: " + "; ".join(texts) if texts else
                                 f"its {kind} row matches (compared after joint {matched + 1})"))
    if not same:
        notes += _base_hints(a, b, joints, params, walked.matched, scale, tol)  # the walks alike, unattributed
    if mapped and not same and first is None:
        diff = next(j for j in joints if j.status != "same")
        first = f"joint {diff.index + 1} ('{diff.name_a}' / '{diff.name_b}'): {diff.detail}"
    # double-check by FK at random q (relative to the robot size): the identity for 'same', the
    # joint mapping for 'equivalent'. Failing here would be a bug in the walk above; say so.
    max_err = math.nan
    if a.n == b.n and a.types == b.types:
        Qb = math.pi * (2.0 * unit_sample(samples, a.n) - 1.0)  # fixed, well spread in [-pi, pi)
        Qa = Qb * (signs if mapped else 1) + (offsets if mapped else 0)
        Ta, Tb = a.fk(Qa), b.fk(Qb)
        max_err = float(np.maximum(np.abs(Ta[:, :3, :3] - Tb[:, :3, :3]).max(axis=(1, 2)),
                                   np.abs(Ta[:, :3, 3] - Tb[:, :3, 3]).max(axis=1) / scale).max())
        if mapped and max_err > 100 * tol:
            notes.append(f"internal check failed: FK under the joint mapping differs by {max_err:.3g}")
            mapped = same = False
            first = first or "FK differs (the joint-by-joint walk could not explain how)"
    return Comparison(same=same, equivalent=mapped, n_a=a.n, n_b=b.n, joints=tuple(joints),
                      first_difference=None if same else first, tool=tool, world=world,
                      max_fk_error=max_err, tol=tol, notes=tuple(notes), parameters=tuple(params), table=kind)


def _base_hints(a: Robot, b: Robot, joints: list[JointMatch], params: list[ParameterDifference], matched: int,
                scale: float, tol: float) -> list[str]:
    """A half turn about joint 1 is nearly always two base frames of the same robot: ROS URDFs of
    Universal Robots arms start at ``base_link`` (x backwards) while UR's DH tables and controller use
    ``base``, turned by pi about z. Seen as joint 1's zero offset pi, or, where the joints differ too,
    as B turned half a turn about joint 1's axis matching more joints of A than B does."""
    from .. import se3

    half = bool(joints) and joints[0].status in ("offset", "sign+offset") and \
        abs(abs(joints[0].offset) - math.pi) <= max(tol, 1e-9)
    if not half and a.n == b.n and b.n and matched < a.n and b.joints[0].revolute and a.types == b.types:
        turned = b.replace(frames=se3.exp_twist(b.screws()[0], math.pi) @ b.frames, frames_from=b.frames_from)
        walk = Walk(a, turned, a.screws(), turned.screws(), scale, tol).run(a.n)
        fewer = len(parameter_differences(a, turned, scale, tol)[1]) < len(params)
        half = walk.matched > matched or (walk.matched == matched and fewer)
    if not half:
        return []
    return ["joint 1 differs by half a turn (pi rad): that is almost always the base frame, not the robot - a "
            "URDF's base_link (ROS, x backwards) against the base of a vendor DH table; compare the URDF from "
            "its vendor base with base_link= (Universal Robots: base_link='base')"]
