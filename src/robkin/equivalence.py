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
The offset of joint i is fixed by the first later axis (or the tool) that it moves: the offset is the
rotation about (slide along) axis i that carries A's next axis onto B's. An offset no later axis
depends on (e.g. two coaxial joints) is carried by the later joint. The first joint whose axis cannot
be matched is reported with how it differs: type, axis direction (angle), or axis position (distance
between the lines; revolute joints only, a prismatic joint is a direction).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from . import se3
from .robot import Robot

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
    status: str  # same | sign | offset | sign+offset | differs | unchecked
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

    def verdict(self) -> str:
        if self.same:
            return "same robot: the tool pose is the same at every q"
        if self.equivalent:
            return ("same mechanism, different joint convention: q_A = sign * q_B + offset per joint "
                    "(see the table)")
        return f"different robots: {self.first_difference}"

    def to_dict(self) -> dict[str, Any]:
        return {"same": self.same, "equivalent": self.equivalent, "verdict": self.verdict(),
                "first_difference": self.first_difference, "joints": [j.to_dict() for j in self.joints],
                "tool": self.tool, "world": self.world,
                "max_fk_error": self.max_fk_error if math.isfinite(self.max_fk_error) else None, "tol": self.tol,
                "n_a": self.n_a, "n_b": self.n_b, "notes": list(self.notes)}


# --------------------------------------------------------------------------------------- helpers
def _scaled(S: np.ndarray, scale: float) -> np.ndarray:
    """Screw (w, v) with v divided by the robot size, so both halves are dimensionless."""
    return np.concatenate([S[:3], S[3:] / scale])


def _screw_error(Sa: np.ndarray, Sb: np.ndarray, scale: float) -> float:
    return float(np.abs(_scaled(Sa, scale) - _scaled(Sb, scale)).max())


def _moved(S: np.ndarray, screw: np.ndarray, amount: float) -> np.ndarray:
    """Screw S carried by the motion exp([screw] amount)."""
    return se3.adjoint(se3.exp_twist(screw, amount)) @ S


def _offset_candidates(pending: np.ndarray, revolute: bool, Sa: np.ndarray, Sb: np.ndarray, scale: float,
                       tol: float) -> tuple[bool, list[tuple[float, int, float]]]:
    """Offsets d of the pending joint (screw ``pending``) with Ad(exp([pending] d)) Sa = sign * Sb.

    Returns (free, candidates): ``free`` if Sa does not move with the pending joint (the offset stays
    undetermined); otherwise (d, sign, residual) for sign = +1 and -1, best first. The moved screw is
    c0 + c1 cos d + c2 sin d for a rotation and c0 + c1 d for a slide, so each d is a 2x2 (1x1)
    least-squares solve in scaled coordinates. Both signs can fit (a rotation by pi about a
    perpendicular axis reverses a line), which is why the caller searches over the candidates.
    """
    s0 = _scaled(Sa, scale)
    if revolute:
        s_half, s_pi = _scaled(_moved(Sa, pending, math.pi / 2), scale), _scaled(_moved(Sa, pending, math.pi), scale)
        c0, c1 = (s0 + s_pi) / 2, (s0 - s_pi) / 2
        c2 = s_half - c0
        if max(np.abs(c1).max(), np.abs(c2).max()) <= tol:
            return True, []
        C = np.column_stack([c1, c2])
    else:
        c0, c1 = s0, _scaled(_moved(Sa, pending, 1.0), scale) - s0
        if np.abs(c1).max() <= tol:
            return True, []
        C = c1[:, None]
    out = []
    for sign in (1, -1):
        target = sign * _scaled(Sb, scale) - c0
        x = np.linalg.lstsq(C, target, rcond=None)[0]
        d = math.atan2(x[1], x[0]) if revolute else float(x[0])
        out.append((d, sign, _screw_error(_moved(Sa, pending, d), sign * Sb, scale)))
    return False, sorted(out, key=lambda c: c[2])


def _tool_offset(pending: np.ndarray, revolute: bool, Ma: np.ndarray, Mb: np.ndarray) -> float:
    """Offset d with exp([pending] d) Ma = Mb (best effort; the caller checks the result)."""
    D = Mb @ se3.inv(Ma)
    if revolute:
        w = pending[:3]
        R = D[:3, :3]
        sin_d = 0.5 * float(np.dot(w, [R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]))
        cos_d = 0.5 * (float(np.trace(R)) - 1.0)
        return math.atan2(sin_d, cos_d)
    return float(np.dot(pending[3:], D[:3, 3]))


def _pose_difference(Ta: np.ndarray, Tb: np.ndarray) -> tuple[float, float]:
    """(translation distance, rotation angle in rad) between two poses."""
    dR = Ta[:3, :3].T @ Tb[:3, :3]
    angle = math.acos(max(-1.0, min(1.0, (float(np.trace(dR)) - 1.0) / 2.0)))
    return float(np.linalg.norm(Ta[:3, 3] - Tb[:3, 3])), angle


def _line(S: np.ndarray, revolute: bool) -> tuple[np.ndarray, np.ndarray]:
    """(direction, point closest to the origin) of a screw's axis (prismatic: through the origin)."""
    if revolute:
        return S[:3], np.cross(S[:3], S[3:])
    return S[3:], np.zeros(3)


def _describe(Sa: np.ndarray, Sb: np.ndarray, revolute: bool) -> str:
    """How two unit screws of the same joint type differ: direction angle, or line distance."""
    ua, pa = _line(Sa, revolute)
    ub, pb = _line(Sb, revolute)
    cosang = float(np.clip(np.dot(ua, ub), -1.0, 1.0))
    angle = math.degrees(math.acos(cosang))
    if revolute:
        from .lines import common_normal

        dist = common_normal(pa, ua, pb, ub).distance
    else:
        dist = 0.0
    if min(angle, 180.0 - angle) > 1e-6:
        text = f"axis direction differs by {angle:.4g} deg"
        if revolute:
            text += f" (axes {dist:.4g} apart at their closest)"
        return text
    way = "the same way" if angle < 90 else "opposite ways"
    return f"axis position differs: parallel axes pointing {way}, {dist:.4g} apart"


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
    notes: list[str] = []
    world_d, world_a = _pose_difference(a.world, b.world)
    world = ("same" if world_d <= tol * scale and world_a <= tol else
             f"differs (position by {world_d:.4g}, rotation by {math.degrees(world_a):.4g} deg); "
             "it places the base in the world and is not part of FK")
    n = min(a.n, b.n)
    joints: list[JointMatch] = []
    first: str | None = None
    if a.n != b.n:
        first = f"joint counts differ: A has {a.n}, B has {b.n}"
    SA, SB = a.screws(), b.screws()
    walk = _Walk(a, b, SA, SB, scale, tol)
    result = walk.run(n)
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
            unit = "rad" if a.joints[k].revolute else ""
            parts.append(f"zero offset {offsets[k]:+.6g} {unit}".rstrip())
        joints[k] = JointMatch(jm.index, jm.name_a, jm.name_b, jm.type_a, jm.type_b, status, int(signs[k]),
                               float(offsets[k]) if shifted else 0.0, "; ".join(parts))
    for k in range(len(joints), n):
        ja, jb = a.joints[k], b.joints[k]
        joints.append(JointMatch(k, ja.name, jb.name, ja.type, jb.type, "unchecked"))
    mapped = all_joints and tool == "same"
    same = mapped and all(j.status == "same" for j in joints)
    if mapped and not same and first is None:
        k = next(j for j in joints if j.status != "same")
        first = f"joint {k.index + 1} ('{k.name_a}' / '{k.name_b}'): {k.detail}"
    # double-check by FK at random q (relative to the robot size): the identity for 'same', the
    # joint mapping for 'equivalent'. Failing here would be a bug in the walk above; say so.
    max_err = math.nan
    if a.n == b.n and a.types == b.types:
        rng = np.random.default_rng(12345)
        Qb = rng.uniform(-math.pi, math.pi, size=(samples, a.n))
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
                      max_fk_error=max_err, tol=tol, notes=tuple(notes))


@dataclass
class _State:
    """A partial joint mapping: G (offsets applied so far), the joint whose offset is still open."""

    G: np.ndarray
    pending: int | None
    signs: np.ndarray
    offsets: np.ndarray


@dataclass
class _Result:
    matched: int
    signs: np.ndarray
    offsets: np.ndarray
    failure: str | None = None
    tool: str = "not compared"


class _Walk:
    """Depth-first search for a joint mapping, preferring sign +1 and offset 0 at every joint.

    At most two candidates per joint (the two signs), and only when a rotation by pi makes both fit,
    so the search is cheap. Without a full mapping, the deepest failure is the diagnosis.
    """

    def __init__(self, a: Robot, b: Robot, SA: np.ndarray, SB: np.ndarray, scale: float, tol: float) -> None:
        self.a, self.b, self.SA, self.SB, self.scale, self.tol = a, b, SA, SB, scale, tol
        self.deepest: _Result | None = None

    def run(self, n: int) -> _Result:
        start = _State(np.eye(4), None, np.ones(n, dtype=int), np.zeros(n))
        found = self._step(0, n, start)
        if found is not None:
            return found
        # a failed search has always recorded where it failed
        return self.deepest or _Result(0, start.signs, start.offsets, "no joint could be matched")

    def _fail(self, i: int, state: _State, why: str, tool: str = "not compared") -> None:
        # keep the first failure at the deepest joint: the search tries the preferred mapping first
        d = self.deepest
        if d is None or i > d.matched or (i == d.matched and d.tool == "not compared" and tool != "not compared"):
            self.deepest = _Result(i, state.signs.copy(), state.offsets.copy(), why, tool)

    def _step(self, i: int, n: int, st: _State) -> _Result | None:
        a, b, tol, scale = self.a, self.b, self.tol, self.scale
        if i == n:
            return self._tool(n, st)
        ja, jb = a.joints[i], b.joints[i]
        if ja.type != jb.type:
            self._fail(i, st, f"type {ja.type} in A, {jb.type} in B")
            return None
        Sa = se3.adjoint(st.G) @ self.SA[i]
        Sb = self.SB[i]
        options: list[tuple[np.ndarray, float | None, int]] = []  # (G, offset of pending, sign)
        explained = ""
        free = True
        if st.pending is not None:
            Sp = se3.adjoint(st.G) @ self.SA[st.pending]
            free, cands = _offset_candidates(Sp, a.joints[st.pending].revolute, Sa, Sb, scale, tol)
            good = [c for c in cands if c[2] <= tol]
            # prefer no offset, then sign +1, then the smaller offset
            good.sort(key=lambda c: (abs(c[0]) > tol, c[1] != 1, abs(c[0])))
            for d, sign, _ in good:
                options.append((se3.exp_twist(Sp, d) @ st.G, d, sign))
            if not free and not good:
                explained = f"; no zero offset of joint {st.pending + 1} explains it"
        if free:
            for sign in (1, -1):
                if _screw_error(Sa, sign * Sb, scale) <= tol:
                    options.append((st.G, None, sign))
        if not options:
            self._fail(i, st, _describe(Sa, Sb, ja.revolute) + explained)
            return None
        for G, d, sign in options:
            nxt = _State(G, i, st.signs.copy(), st.offsets.copy())
            nxt.signs[i] = sign
            if d is not None:
                nxt.offsets[st.pending] = d
            found = self._step(i + 1, n, nxt)
            if found is not None:
                return found
        return None

    def _tool(self, n: int, st: _State) -> _Result | None:
        tol, scale = self.tol, self.scale
        Ma = st.G @ self.a.tool
        offsets = st.offsets.copy()
        if st.pending is not None:
            Sp = se3.adjoint(st.G) @ self.SA[st.pending]
            d = _tool_offset(Sp, self.a.joints[st.pending].revolute, Ma, self.b.tool)
            E = se3.exp_twist(Sp, d)
            dist, ang = _pose_difference(E @ Ma, self.b.tool)
            if dist <= tol * scale and ang <= tol:
                offsets[st.pending] = d
                Ma = E @ Ma
        dist, ang = _pose_difference(Ma, self.b.tool)
        if dist <= tol * scale and ang <= tol:
            return _Result(n, st.signs.copy(), offsets, None, "same")
        self._fail(n, replace(st, offsets=offsets), "",
                   f"differs: position by {dist:.4g}, rotation by {math.degrees(ang):.4g} deg")
        return None
