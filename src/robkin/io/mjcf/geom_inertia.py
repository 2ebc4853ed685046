"""The mass properties MuJoCo gives a geom: volume (or area) and principal moments of each primitive, and
a mesh's volume, centre and inertia in each of MuJoCo's mesh inertia modes.

Written from the geometry, in MuJoCo's conventions (``size`` as the MJCF ``size``: radii and half lengths),
so that a body whose mass comes from its geoms gets the numbers MuJoCo compiles (checked against MuJoCo
in ``tests/test_mjcf_mass.py``).

Primitives (``primitive_measure``, ``primitive_moments``), solid (density is mass per volume) or, with
``shellinertia``, a thin shell (mass per area):

* sphere (r); box (half sides a, b, c); cylinder (r, half length h), z along its axis;
* capsule (r, half length h): a cylinder and two half-sphere caps, each cap's own moment about its centre
  of mass shifted to the capsule's centre (solid: the cap's centre is 3r/8 from its flat face; shell:
  r/2);
* ellipsoid (a, b, c). Its shell is MuJoCo's approximation: the area by Thomsen's formula, the moments as
  the difference of two solid ellipsoids 1e-6 apart (MuJoCo's own arithmetic, kept as it is).

Meshes (``mesh_mass``): the divergence theorem over the triangles, each triangle with a reference point
making a tetrahedron (volume modes) or the triangle itself (``shell``):

* ``exact``: signed tetrahedra (a closed, consistently oriented mesh);
* ``legacy`` (MuJoCo's default): every tetrahedron counted positive, from the area-weighted centre of
  the faces for the centre of mass, then from that centre for the volume and the moments (this
  over-counts a mesh that is not convex, as MuJoCo does);
* ``convex``: ``exact`` on the convex hull (qhull, through ``scipy.spatial.ConvexHull``: the library
  MuJoCo uses, so ``maxhullvert`` is honoured the same way);
* ``shell``: mass on the surface, by area.

Vertices are rounded to float32 first and then scaled (MuJoCo keeps mesh vertices as float32).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["PRIMITIVE_KINDS", "MESH_INERTIA", "primitive_measure", "primitive_moments", "mesh_mass",
           "MeshMass"]

#: the primitive geom types that carry mass
PRIMITIVE_KINDS = ("sphere", "capsule", "cylinder", "ellipsoid", "box")
#: MuJoCo's ``<mesh inertia>`` modes; its default (MuJoCo 3.x and 4.0) is legacy
MESH_INERTIA = ("legacy", "convex", "exact", "shell")
#: MuJoCo's mjMINVAL: a mesh area or volume below it is refused
MIN_VALUE = 1e-15
_PI = math.pi


def primitive_measure(kind: str, size: tuple[float, float, float], shell: bool) -> float:
    """Volume (solid) or surface area (``shell``) of a primitive geom, MJCF sizes."""
    s0, s1, s2 = size
    if kind == "sphere":
        return 4 * _PI * s0 * s0 if shell else 4 * _PI * s0 * s0 * s0 / 3
    if kind == "capsule":
        h = 2 * s1
        return 4 * _PI * s0 * s0 + 2 * _PI * s0 * h if shell else _PI * (s0 * s0 * h + 4 * s0 * s0 * s0 / 3)
    if kind == "cylinder":
        h = 2 * s1
        return 2 * _PI * s0 * s0 + 2 * _PI * s0 * h if shell else _PI * s0 * s0 * h
    if kind == "ellipsoid":
        if not shell:
            return 4 * _PI * s0 * s1 * s2 / 3
        p = 1.6075  # Thomsen's approximation of an ellipsoid's area (within 1.061 %)
        t = (s0 * s1) ** p + (s1 * s2) ** p + (s2 * s0) ** p
        return 4 * _PI * (t / 3) ** (1 / p)
    if kind == "box":
        return 8 * (s0 * s1 + s1 * s2 + s2 * s0) if shell else s0 * s1 * s2 * 8
    raise ValueError(kind)


def primitive_moments(kind: str, size: tuple[float, float, float], mass: float, shell: bool) -> np.ndarray:
    """Principal moments (3,) about the centre, in the geom's frame, of a primitive of ``mass``."""
    s0, s1, s2 = size
    m = mass
    if kind == "sphere":
        k = 2 * m * s0 * s0 / 3 if shell else 2 * m * s0 * s0 / 5
        return np.array([k, k, k])
    if kind == "cylinder":
        r, hh = s0, s1
        h = 2 * hh
        if not shell:
            x = m * (3 * r * r + h * h) / 12
            return np.array([x, x, m * r * r / 2])
        disk = _PI * r * r
        total = 2 * disk + 2 * _PI * r * h
        m_disk = m * disk / total
        m_tube = m - 2 * m_disk
        x = m_tube * (6 * r * r + h * h) / 12 + 2 * (m_disk * r * r / 4 + m_disk * hh * hh)
        return np.array([x, x, m_tube * r * r + 2 * (m_disk * r * r / 2)])
    if kind == "capsule":
        r, hh = s0, s1
        h = 2 * hh
        if not shell:
            m_caps = m * 4 * r / (4 * r + 3 * h)       # the two caps' share of the volume
            m_tube = m - m_caps
            cap = 2 * m_caps * r * r / 5
            x = m_tube * (3 * r * r + h * h) / 12 + cap + m_caps * h * (3 * r + 2 * h) / 8
            return np.array([x, x, m_tube * r * r / 2 + cap])
        a_caps = 4 * _PI * r * r
        m_caps = m * a_caps / (a_caps + 2 * _PI * r * h)
        m_tube = m - m_caps
        cap = 2 * m_caps * r * r / 3
        centre = r / 2                                  # a half-sphere shell's centre, from its flat face
        at = hh + centre
        x = m_tube * (6 * r * r + h * h) / 12 + cap + m_caps * (at * at - centre * centre)
        return np.array([x, x, m_tube * r * r + cap])
    if kind == "ellipsoid":
        a2, b2, c2 = s0 * s0, s1 * s1, s2 * s2
        if not shell:
            return np.array([m * (b2 + c2) / 5, m * (a2 + c2) / 5, m * (a2 + b2) / 5])
        eps = 1e-6                                     # MuJoCo's: a solid shell of this thickness
        va = 4 * _PI * s0 * s1 * s2 / 3
        ae, be, ce = s0 + eps, s1 + eps, s2 + eps
        vb = 4 * _PI * ae * be * ce / 3
        rho = m / (vb - va)
        ma, mb = va * rho, vb * rho
        return np.array([mb * (be * be + ce * ce) / 5 - ma * (b2 + c2) / 5,
                         mb * (ae * ae + ce * ce) / 5 - ma * (a2 + c2) / 5,
                         mb * (ae * ae + be * be) / 5 - ma * (a2 + b2) / 5])
    if kind == "box":
        if not shell:
            a2, b2, c2 = s0 * s0, s1 * s1, s2 * s2
            return np.array([m * (b2 + c2) / 3, m * (a2 + c2) / 3, m * (a2 + b2) / 3])
        lx, ly, lz = 2 * s0, 2 * s1, 2 * s2
        a0, a1, a2_ = lx * ly, ly * lz, lz * lx         # the faces normal to z, x, y
        total = 2 * (a0 + a1 + a2_)
        m0, m1, m2 = m * a0 / total, m * a1 / total, m * a2_ / total
        x = 2 * (m0 * s2 * s2 + m2 * s1 * s1 + m0 * ly * ly / 12 + m1 * (ly * ly + lz * lz) / 12 + m2 * lz * lz / 12)
        y = 2 * (m0 * s2 * s2 + m1 * s0 * s0 + m0 * lx * lx / 12 + m1 * lz * lz / 12 + m2 * (lx * lx + lz * lz) / 12)
        z = 2 * (m1 * s0 * s0 + m2 * s1 * s1 + m0 * (lx * lx + ly * ly) / 12 + m1 * ly * ly / 12 + m2 * lx * lx / 12)
        return np.array([x, y, z])
    raise ValueError(kind)


class MeshMass:
    """A mesh's measure (volume, or area for ``shell``), centre (3,) and inertia (3, 3) per unit density
    about that centre, all in the mesh's own (scaled) coordinates."""

    def __init__(self, measure: float, centre: np.ndarray, inertia: np.ndarray):
        self.measure, self.centre, self.inertia = measure, centre, inertia


def _triangles(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(area (k,), unit normal (k, 3), centre (k, 3), corners (k, 3, 3)) of the triangles."""
    corners = v[f]
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    norm = np.linalg.norm(cross, axis=1)
    area = norm / 2
    normal = np.divide(cross, norm[:, None], out=np.zeros_like(cross), where=norm[:, None] > 0)
    return area, normal, corners.mean(axis=1), corners


def _second_moments(corners: np.ndarray, weight: np.ndarray, denominator: float) -> np.ndarray:
    """Sum over triangles (corners D, E, F relative to the point of reference) of
    weight / denominator * (2 (DD + EE + FF) + DE + ED + DF + FD + EF + FE): (3, 3)."""
    s = corners.sum(axis=1)
    outer = np.einsum("kai,kaj->kij", corners, corners) + np.einsum("ki,kj->kij", s, s)
    return np.einsum("k,kij->ij", weight / denominator, outer)


def _inertia_from_moments(P: np.ndarray) -> np.ndarray:
    """The inertia tensor of second moments P (the integrals of x_i x_j)."""
    return np.trace(P) * np.eye(3) - P


def hull_faces(v: np.ndarray, maxhullvert: int = -1) -> np.ndarray:
    """Outward-oriented triangles (k, 3) of the convex hull of ``v`` (qhull, MuJoCo's options)."""
    from scipy.spatial import ConvexHull

    options = "Qt" + (f" Q9 TA{maxhullvert - 4}" if maxhullvert > -1 else "")
    hull = ConvexHull(v, qhull_options=options)
    f = hull.simplices.copy()
    tri = v[f]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    flip = np.einsum("ki,ki->k", n, hull.equations[:, :3]) < 0
    f[flip] = f[flip][:, [0, 2, 1]]
    return f


def mesh_mass(vertices: np.ndarray, faces: np.ndarray, mode: str, maxhullvert: int = -1) -> MeshMass:
    """Volume (or area), centre and unit-density inertia of a mesh in MuJoCo's ``mode`` (see the module doc).

    ``vertices`` (nv, 3) already scaled; ``faces`` (nf, 3) indices (for ``convex`` the hull is made here;
    an empty ``faces`` means the hull in every mode, as MuJoCo does for a mesh given by points).
    Raises ValueError with MuJoCo's reason when MuJoCo would refuse the mesh.
    """
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.intp).reshape(-1, 3)
    if len(f) == 0:
        f = hull_faces(v, maxhullvert)
    area, normal, centre, _ = _triangles(v, f)
    total_area = float(area.sum())
    if total_area < MIN_VALUE:
        raise ValueError("mesh surface area is too small")
    facecen = (area[:, None] * centre).sum(axis=0) / total_area
    if mode == "convex":
        f = hull_faces(v, maxhullvert)
        area, normal, centre, _ = _triangles(v, f)
    if mode == "shell":
        com = facecen  # MuJoCo's (3/4 centre + 1/4 face centroid) weighted by area: the area centroid
    else:
        vol = np.einsum("ki,ki->k", centre - facecen, normal) * area / 3
        if mode == "legacy":
            vol = np.abs(vol)
        total = float(vol.sum())
        if total < MIN_VALUE:
            raise ValueError("mesh volume is negative (misoriented triangles)" if total < 0
                             else "mesh volume is too small (try <mesh inertia=\"shell\">)")
        com = (vol[:, None] * (centre * 0.75 + facecen * 0.25)).sum(axis=0) / total
    corners = v[f] - com
    c_area, c_normal, c_centre, _ = _triangles(v - com, f)
    if mode == "shell":
        weight = c_area
        P = _second_moments(corners, weight, 12.0)
    else:
        weight = np.einsum("ki,ki->k", c_centre, c_normal) * c_area / 3
        if mode == "legacy":
            weight = np.abs(weight)
        P = _second_moments(corners, weight, 20.0)
    measure = float(weight.sum())
    return MeshMass(measure, com, _inertia_from_moments(P))
