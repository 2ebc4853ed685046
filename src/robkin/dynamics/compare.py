"""Do two descriptions of the same mechanism carry the same mass properties?

``robkin check A B`` first decides whether A and B are the same mechanism (``robkin.equivalence.comparison``: the
same robot, or the same under a joint mapping q_A = s q_B + delta). Then, where both give inertials,
this module compares what moves: body by body (mass, centre of mass, inertia about it, in the base
frame at B's home configuration, A's bodies moved to q_A = delta), and the joint-space mass matrix M(q)
and gravity torques g(q) at fixed, well-spread configurations, with gravity along -z of each robot's
base (so a different world placement does not count). The first body that differs is named, as the
equivalence check names the first joint.

Tolerances are relative, as the kinematic check's ``tol``: masses to the larger mass, centres to the
robot's size, inertias to the body's inertia scale (its largest entry, or mass times size squared),
M and g to their largest entry. M(q) is the bodies' own: joint armature (a rotor's inertia, MJCF) is left
out of it, and a difference in armature is said in the notes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..io.files.float_text import distinct_texts
from ..samples import unit_sample
from ..mass_properties import LinkMasses, link_masses

if TYPE_CHECKING:  # pragma: no cover
    from ..equivalence.comparison import Comparison
    from ..robot import Robot

__all__ = ["BodyMatch", "MassComparison", "compare_masses", "same_robot"]

#: gravity along -z of the robot base (m/s^2), for the g(q) comparison
_DOWN = np.array([0.0, 0.0, -9.81])


@dataclass(frozen=True)
class BodyMatch:
    """Body i of A against body i of B (body 0 is fixed to the base; body i moves with joint i)."""

    index: int
    name_a: str
    name_b: str
    mass_a: float
    mass_b: float
    centre_distance: float      # m, between the centres of mass
    inertia_difference: float   # kg m^2, largest entry of the difference (base-frame axes)
    same: bool

    def to_dict(self) -> dict[str, Any]:
        return {"body": self.index, "name_a": self.name_a, "name_b": self.name_b, "mass_a": self.mass_a,
                "mass_b": self.mass_b, "centre_distance": self.centre_distance,
                "inertia_difference": self.inertia_difference, "same": self.same}


@dataclass(frozen=True)
class MassComparison:
    """Result of ``compare_masses``.

    ``checked`` is False when a side has no mass properties or the mechanisms differ (``reason`` says
    which); then ``same`` is None. Errors of M and g are relative to their largest entry.
    """

    checked: bool
    same: bool | None
    reason: str = ""
    bodies: tuple[BodyMatch, ...] = ()
    first_difference: str | None = None
    total_mass_a: float = math.nan
    total_mass_b: float = math.nan
    mass_matrix_error: float = math.nan
    gravity_error: float = math.nan
    samples: int = 0
    notes: tuple[str, ...] = field(default_factory=tuple)

    def summary(self) -> str:
        """One line, as ``robkin check`` prints it."""
        if not self.checked:
            return f"mass properties: not compared ({self.reason})"
        ta, tb = distinct_texts(self.total_mass_a, self.total_mass_b) if not self.same else \
            (f"{self.total_mass_a:.6g}", f"{self.total_mass_b:.6g}")
        head = (f"mass properties: {'same' if self.same else 'DIFFER'} ({len(self.bodies)} bodies, total "
                f"{ta} kg vs {tb} kg; M(q) and g(q) at {self.samples} "
                f"configurations differ by {self.mass_matrix_error:.2g} and {self.gravity_error:.2g} of their "
                f"largest entry)")
        return head if self.same else f"{head}; first difference: {self.first_difference}"

    def to_dict(self) -> dict[str, Any]:
        def num(x: float) -> float | None:
            return x if math.isfinite(x) else None

        return {"checked": self.checked, "same": self.same, "reason": self.reason,
                "first_difference": self.first_difference, "total_mass_a": num(self.total_mass_a),
                "total_mass_b": num(self.total_mass_b), "mass_matrix_error": num(self.mass_matrix_error),
                "gravity_error": num(self.gravity_error), "samples": self.samples,
                "bodies": [b.to_dict() for b in self.bodies], "notes": list(self.notes)}


def _body_names(robot: "Robot") -> list[str]:
    chain = robot.bodies.chain
    return list(chain) if len(chain) == robot.n + 1 else [f"body {i}" for i in range(robot.n + 1)]


def _moved(robot: "Robot", masses: LinkMasses, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centres (n+1, 3) and inertias (n+1, 3, 3) of the bodies moved from q = 0 to q (base frame)."""
    from ..bodies import body_motions

    motion = body_motions(robot, q)
    R, p = motion[:, :3, :3], motion[:, :3, 3]
    com = np.einsum("kij,kj->ki", R, masses.com) + p
    inertia = R @ masses.inertia @ R.transpose(0, 2, 1)
    return com, inertia


def _relative(a: np.ndarray, b: np.ndarray, floor: float = 0.0) -> float:
    """Largest difference relative to the largest entry, or to ``floor`` when that is larger: where
    every entry is 0 but for rounding (g(q) of a robot whose axes are all vertical, 1e-17 N m) the
    noise is no difference."""
    scale = max(float(np.abs(a).max(initial=0.0)), float(np.abs(b).max(initial=0.0)), floor)
    return float(np.abs(a - b).max(initial=0.0)) / scale if scale > 0 else 0.0


def _rigid(robot: "Robot", M: np.ndarray) -> np.ndarray:
    """M(q) of the bodies alone: the joints' armature (not a mass property of a body) taken off its diagonal."""
    from .rigid_body import armature

    arm = armature(robot)
    if arm is not None:
        i = np.arange(robot.n)
        M[..., i, i] -= arm
    return M


def compare_masses(a: "Robot", b: "Robot", kinematics: "Comparison", samples: int = 16) -> MassComparison:
    """Compare the mass properties of A and B, given their kinematic comparison.

    Parameters
    ----------
    a, b : Robot
    kinematics : Comparison
        ``robkin.equivalence.compare(a, b)``: its joint mapping (signs, offsets) relates the bodies, and
        its ``tol`` is used here.
    samples : int
        Configurations at which M(q) and g(q) are compared (fixed, spread over [-pi, pi)).
    """
    ma, mb = link_masses(a), link_masses(b)
    if ma is None or mb is None:
        reason = ("neither A nor B has inertials" if ma is None and mb is None else
                  f"{'A' if ma is None else 'B'} has no inertials")
        return MassComparison(checked=False, same=None, reason=reason)
    if not kinematics.equivalent:
        return MassComparison(checked=False, same=None, reason="the kinematics differ, so the bodies do not correspond")
    tol = kinematics.tol
    scale = max(a.scale, b.scale, 1e-100)
    signs = np.array([j.sign for j in kinematics.joints], dtype=float)
    offsets = np.array([j.offset for j in kinematics.joints], dtype=float)
    com_a, inertia_a = _moved(a, ma, offsets)   # A's bodies where B's are at its home configuration
    names_a, names_b = _body_names(a), _body_names(b)
    bodies: list[BodyMatch] = []
    first: str | None = None
    for i in range(a.n + 1):
        m1, m2 = float(ma.mass[i]), float(mb.mass[i])
        dist = float(np.linalg.norm(com_a[i] - mb.com[i])) if m1 > 0 and m2 > 0 else 0.0
        dI = float(np.abs(inertia_a[i] - mb.inertia[i]).max())
        inertia_scale = max(float(np.abs(inertia_a[i]).max()), float(np.abs(mb.inertia[i]).max()),
                            max(m1, m2) * scale * scale)
        same = (abs(m1 - m2) <= tol * max(m1, m2) and dist <= tol * scale and dI <= tol * inertia_scale)
        bodies.append(BodyMatch(i, names_a[i], names_b[i], m1, m2, dist, dI, same))
        if not same and first is None:
            what = []
            if abs(m1 - m2) > tol * max(m1, m2):
                what.append("mass {} kg vs {} kg".format(*distinct_texts(m1, m2)))  # digits enough to differ
            if dist > tol * scale:
                what.append(f"centre of mass {dist:.4g} m apart")
            if dI > tol * inertia_scale:
                what.append(f"inertia differs by {dI:.4g} kg m^2")
            first = f"body {i} ('{names_a[i]}' / '{names_b[i]}'): {', '.join(what)}"
    # M(q) and g(q) under the joint mapping: M_B(q) = S M_A(s q + delta) S, g_B(q) = S g_A(s q + delta)
    Qb = math.pi * (2.0 * unit_sample(samples, a.n) - 1.0)
    Qa = Qb * signs + offsets
    ga, gb = a.world[:3, :3] @ _DOWN, b.world[:3, :3] @ _DOWN   # -z of each base, in its world frame
    Ma = _rigid(a, a.mass_matrix(Qa)) * signs[None, :, None] * signs[None, None, :]
    Ga = a.gravity(Qa, gravity=ga) * signs
    # floors: a thousandth of the moving mass at one robot size (its inertia there, its weight's torque
    # there), far below the entries of any robot whose M or g is not 0 by its geometry (UR5: 17 kg,
    # largest M entry ~3 kg m^2), far above rounding noise (1e-17)
    moving = 1e-3 * max(float(ma.mass[1:].sum()), float(mb.mass[1:].sum()))
    M_err = _relative(Ma, _rigid(b, b.mass_matrix(Qb)), moving * scale * scale)
    g_err = _relative(Ga, b.gravity(Qb, gravity=gb), float(np.linalg.norm(_DOWN)) * moving * scale)
    notes = []
    arm_a, arm_b = ([j.armature or 0.0 for j in r.joints] for r in (a, b))
    if arm_a != arm_b:
        notes.append(f"joint armature differs (A {arm_a}, B {arm_b}): M(q) is compared without it")
    moving_same = all(body.same for body in bodies[1:])
    if not bodies[0].same:
        notes.append("the base bodies differ (body 0 never moves: no effect on the joint torques)")
    same = all(body.same for body in bodies) and M_err <= tol and g_err <= tol
    if first is None and not same:
        first = (f"M(q) differs by {M_err:.3g} and g(q) by {g_err:.3g} of their largest entry"
                 if moving_same else first)
    return MassComparison(checked=True, same=same, bodies=tuple(bodies), first_difference=first,
                          total_mass_a=ma.total_mass, total_mass_b=mb.total_mass, mass_matrix_error=M_err,
                          gravity_error=g_err, samples=samples, notes=tuple(notes))


def same_robot(kinematics: "Comparison", masses: MassComparison) -> bool:
    """``robkin check A B``'s verdict (exit status 0), which the GUI's visual check shows too: the same
    mechanism (``kinematics``, from ``equivalence.compare``), and ``masses`` (from ``compare_masses``) that
    agree or that one side does not give (``masses.same`` None)."""
    return bool(kinematics.same and masses.same is not False)
