"""Mass-property checks of a URDF's links: missing or zero mass on moving bodies, inertia validity
(positive definite, triangle inequality), centre of mass against the geometry, density and inertia
against the collision volume, placeholder values.

Bands (``DENSITY_BAND``, ``GYRATION_BAND``) are wide on purpose: a robot link is a hollow shell of
aluminium or plastic around motors, modelled by a solid collision volume, so its apparent density sits
far below aluminium's; the bands catch unit and placeholder mistakes (factors of 1000), not design.
"""

from __future__ import annotations

import numpy as np

from .findings import ERROR, WARNING, Finding
from .geometry import MeshCache, link_solid
from .structure import moving_links, poses_in_group, rigid_groups
from .urdf_source import RawUrdf

__all__ = ["mass_findings", "DENSITY_BAND", "GYRATION_BAND", "MIN_VALUE", "principal"]

#: MuJoCo's mjMINVAL: a moving body's mass and each principal moment must be above it
MIN_VALUE = 1e-15
#: plausible apparent density of a link (kg/m^3) over its solid collision volume: from a hollow shell of
#: plastic (~20: a 1 mm wall of a 10 cm part) to above osmium (22 590); outside it a unit or placeholder mistake
DENSITY_BAND = (20.0, 25_000.0)
#: plausible ratio of the stated inertia's trace to that of the solid collision geometry of the same mass:
#: a point mass is ~0, a thin shell at most 5/3 of the solid; a factor of 100 below is a mistake (the upper side
#: is a hard bound instead: no mass inside the geometry's box has a trace above 2 m r_max^2)
GYRATION_BAND = (0.01, 10.0)
#: the bound tr(I) <= 2 m r_max^2 is flagged only beyond this fraction: meshes simplify the real part and
#: identified inertias carry errors of some per cent
INERTIA_SLACK = 0.25
#: below this mass (kg) a link is a frame's dummy (a sensor or tool frame): no density or placeholder checks
NEGLIGIBLE_MASS = 0.01
#: c * identity with c below this many kg m^2 per kg (a radius of gyration under 0.1 mm) is a placeholder
PLACEHOLDER_TINY = 1e-8
_FIX_I = ("--fix replaces it by the nearest valid tensor (--inertia nearest) or the collision geometry's at the "
          "link's mass (--inertia geometry)")
#: triangle inequality A + B >= C is checked with this relative slack (rounding of written values)
TRIANGLE_TOL = 1e-9


def principal(I: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (ascending) and axes (columns) of a symmetric 3x3."""
    w, R = np.linalg.eigh((I + I.T) / 2)
    return w, R


def mass_findings(u: RawUrdf, meshes: MeshCache) -> list[Finding]:
    f: list[Finding] = []
    moving = moving_links(u)
    groups = rigid_groups(u)
    group_inertia = merged_groups(u, groups)[1]
    group_mass: dict[str, float] = {}
    for ln in u.links:
        if ln.mass and ln.mass > 0:
            head = groups.get(ln.name, ln.name)
            group_mass[head] = group_mass.get(head, 0.0) + ln.mass
    # the link that speaks for a rigid group: its head, or (a head robkin's reader made: MJCF BODY/JOINT,
    # SDF CHILD@JOINT) the first link of the group written in the file; none for a group of made links only
    speaker: dict[str, str] = {}
    for ln in u.links:
        head = groups.get(ln.name, ln.name)
        if not ln.frame_only and (ln.name == head or head not in speaker):
            speaker[head] = ln.name
    for ln in u.links:
        el = f"{u.link_word} '{ln.name}'"
        line = ln.inertial_line or ln.line

        def add(sev, code, message, fix, at=line):
            f.append(Finding(sev, code, u.file, at, el, message, fix))

        if ln.has_inertial and ln.mass is None:
            add(ERROR, "mass-malformed", f"<mass value='{ln.mass_text}'> is missing or not a number", "write the mass in kg")
            continue
        if ln.mass is not None and ln.mass < 0:
            add(ERROR, "mass-negative", f"mass {ln.mass:g} kg is negative", "give the link its mass (kg, > 0)")
            continue
        head = groups.get(ln.name, ln.name)
        is_head = ln.name in moving and speaker.get(head) == ln.name
        if is_head and group_mass.get(head, 0.0) <= MIN_VALUE and u.fmt == "sdf" and not ln.has_inertial:
            add(WARNING, "mass-default", "a moving link with no <inertial> (nor any link fixed to it): SDFormat's "
                "default of 1 kg and a unit inertia (1 kg m^2 about each axis) applies in Gazebo and drake: a "
                "placeholder, not the link's", "write the link's <inertial> (mass, pose, inertia) from CAD")
            continue
        if is_head and group_mass.get(head, 0.0) <= MIN_VALUE:
            has_geoms = any(g.role == "collision" for g in ln.geometries)
            if u.fmt == "mjcf":  # the reader has done what MuJoCo does: the geoms' mass is in ln.mass already
                mujoco_says = ("MuJoCo refuses it ('mass and inertia of moving bodies must be larger than "
                               "mjMINVAL'; its geoms, at their density, give it none)")
            elif not ln.has_inertial and has_geoms:
                mujoco_says = ("MuJoCo silently gives it the mass of its collision shapes at 1000 kg/m^3 "
                               "(inertiafromgeom auto)")
            else:
                mujoco_says = "MuJoCo refuses it ('mass and inertia of moving bodies must be larger than mjMINVAL')"
            what = "no <inertial>" if not ln.has_inertial else f"mass {ln.mass:g} kg"
            add(ERROR, "mass-zero-moving",
                f"a moving link with {what} (nor any link fixed to it): {mujoco_says}; pinocchio and drake get a "
                f"massless body (a singular mass matrix where nothing below carries mass)", "give the link its mass "
                "and inertia (--fix derives them from the collision geometry at --density)")
            continue
        if ln.has_inertial and ln.mass == 0 and ln.inertia is not None and np.any(ln.inertia != 0):
            add(WARNING, "inertia-without-mass", f"mass 0 with a nonzero inertia (principal moments "
                f"{_g(principal(ln.inertia)[0])} kg m^2): no mass distribution has it; pinocchio keeps the rotational "
                "inertia, MuJoCo's M(q) of robkin's MJCF export lacks it (observed: pybullet's Panda, 0.1 on "
                "each revolute joint's diagonal entry)",
                "give the link its mass, or write its inertia as 0")
        if not ln.has_inertial or not ln.mass:
            continue
        if ln.inertia is None:
            add(ERROR, "inertia-malformed", "<inertial> has a mass but no complete <inertia ixx iyy izz ixy iyz ixz>",
                "write all six inertia values (kg m^2)")
            continue
        w, _ = principal(ln.inertia)
        # MuJoCo 4.0 (observed) refuses these on every link, moving, fixed to a moving one or the fixed base;
        # an all-zero inertia is a point mass, which it takes where the body it is fused into has inertia
        if np.any(ln.inertia != 0) and w[0] < MIN_VALUE:
            what = "not positive definite" if w[0] < 0 else "singular (a moment is zero)"
            add(ERROR, "inertia-not-positive", f"inertia is {what}: principal moments {_g(w)} kg m^2; MuJoCo refuses "
                "it ('inertia must have positive eigenvalues'), drake warns and substitutes a plausible inertia, "
                "pinocchio loads a non-physical body", _FIX_I)
            continue
        if w[0] + w[1] < w[2] * (1 - TRIANGLE_TOL):
            add(ERROR, "inertia-triangle", f"principal moments {_g(w)} kg m^2 violate the triangle inequality "
                f"A + B >= C (no mass distribution has them): MuJoCo refuses it ('use balanceinertia to fix'), "
                f"drake warns and substitutes a plausible inertia, pinocchio loads it as it is", _FIX_I)
            continue
        gw = principal(group_inertia[head])[0] if head in group_inertia and is_head else None
        if is_head and gw is not None and gw[0] <= MIN_VALUE:
            add(ERROR, "inertia-singular", f"inertia is rank-deficient (principal moments {_g(gw)} kg m^2, with the "
                "links fixed to it): MuJoCo refuses it ('mass and inertia of moving bodies must be larger than "
                "mjMINVAL'), pinocchio's forward dynamics divides by zero", _FIX_I)
            continue
        if ln.mass < NEGLIGIBLE_MASS:
            continue  # a frame's dummy mass: it changes no dynamics, whatever its inertia and geometry
        diag = np.diag(ln.inertia)
        if np.count_nonzero(ln.inertia - np.diag(diag)) == 0 and np.all(diag == diag[0]) and \
                (diag[0] in (1.0, 0.1, 0.01) or 0 < diag[0] <= PLACEHOLDER_TINY * ln.mass):
            add(WARNING, "inertia-placeholder", f"inertia is {diag[0]:g} * identity with mass {ln.mass:g} kg: "
                "it looks like a placeholder (an exporter's default), not the link's", "--fix --inertia geometry "
                "replaces it by the collision geometry's at the stated mass, or take it from CAD")
        solid = link_solid(ln, meshes)
        if solid is None or solid.volume <= 0:
            continue
        density = ln.mass / solid.volume
        if not DENSITY_BAND[0] <= density <= DENSITY_BAND[1]:
            add(WARNING, "mass-vs-volume", f"mass {ln.mass:g} kg over the collision volume {solid.volume:.3g} m^3 "
                f"is {density:.3g} kg/m^3, outside the plausible band {DENSITY_BAND[0]:g}-{DENSITY_BAND[1]:g} "
                "kg/m^3 (a unit mistake: grams or millimetres?)", "check the mass's unit (kg) and the geometry's (m)")
        trace = float(np.trace(ln.inertia))
        corners = np.array([[x, y, z] for x in (solid.lo[0], solid.hi[0]) for y in (solid.lo[1], solid.hi[1])
                            for z in (solid.lo[2], solid.hi[2])])
        reach = float(np.max(np.sum((corners - ln.com) ** 2, axis=1)))
        solid_trace = float(np.trace(solid.inertia)) * ln.mass / solid.volume
        if trace > 2 * ln.mass * reach * (1 + INERTIA_SLACK):
            add(WARNING, "inertia-too-large", f"inertia trace {trace:.4g} kg m^2 is more than any {ln.mass:g} kg "
                f"inside the link's geometry can have (2 m r^2 = {2 * ln.mass * reach:.4g}, r the farthest "
                f"corner of its shapes' box from the centre of mass; {trace / solid_trace:.3g} x the solid geometry's): the "
                "dynamics will be too sluggish", "check the inertia's unit (kg m^2), frame and the mass; "
                "--fix --inertia geometry takes the collision geometry's")
        elif 0 < trace < GYRATION_BAND[0] * solid_trace:
            add(WARNING, "inertia-vs-geometry", f"inertia trace is {trace / solid_trace:.3g} x the solid collision "
                f"geometry's at the same mass (below {GYRATION_BAND[0]:g}: nearly a point mass): the link will turn "
                f"{solid_trace / trace:.3g} times too easily", "check the inertia's unit (kg m^2); "
                "--fix --inertia geometry takes the collision geometry's")
        size = solid.hi - solid.lo
        out = np.maximum(0, np.maximum(solid.lo - ln.com, ln.com - solid.hi))
        if np.linalg.norm(out) > max(0.5 * float(np.linalg.norm(size)), 0.05):
            add(WARNING, "com-outside", f"centre of mass {_g(ln.com)} m is {np.linalg.norm(out):.3g} m outside the "
                f"link's geometry (box {_g(solid.lo)} to {_g(solid.hi)} m)", "check <inertial><origin> (frame, unit, sign)")
    return f


def merged_groups(u: RawUrdf, groups: dict[str, str]) -> tuple[dict[str, float], dict[str, np.ndarray]]:
    """Head link -> total mass and inertia (3, 3) about the group's centre of mass, in the head's axes, of the
    links fixed to it (as MuJoCo, pinocchio and drake fuse them); links with malformed values are left out."""
    poses = poses_in_group(u)
    parts: dict[str, list] = {}
    for ln in u.links:
        if ln.mass and ln.mass > 0 and ln.inertia is not None:
            T = poses[ln.name]
            R = T[:3, :3]
            parts.setdefault(groups.get(ln.name, ln.name), []).append(
                (ln.mass, T[:3, :3] @ ln.com + T[:3, 3], R @ ln.inertia @ R.T))
    mass, inertia = {}, {}
    for head, items in parts.items():
        m = sum(p[0] for p in items)
        c = sum(p[0] * p[1] for p in items) / m
        I = np.zeros((3, 3))
        for mi, ci, Ii in items:
            d = ci - c
            I += Ii + mi * (d @ d * np.eye(3) - np.outer(d, d))
        mass[head], inertia[head] = m, I
    return mass, inertia


def _g(v) -> str:
    return "(" + ", ".join(f"{x:.4g}" for x in v) + ")"
