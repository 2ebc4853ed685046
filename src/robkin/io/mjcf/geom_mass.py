"""A body's mass properties as MuJoCo compiles them: from its ``<inertial>``, or from its geoms.

MuJoCo's rules (its XML reference: ``compiler``, ``geom``, ``mesh``), followed here so that M(q), g(q)
and inverse dynamics of an MJCF model are MuJoCo's:

``<compiler inertiafromgeom>``
    ``auto`` (default): a body without ``<inertial>`` takes the mass of its geoms; ``true``: every body
    does, its ``<inertial>`` ignored; ``false``: only ``<inertial>`` counts (a body without one is
    massless). The world body never takes mass.
``<compiler inertiagrouprange>`` (default 0 5)
    Only geoms whose ``group`` lies in the range count.
A geom's mass
    Its ``mass`` if given (0: none), else ``density`` (default 1000) times its volume; with
    ``shellinertia="true"`` a primitive is a thin shell and density is per area. Meshes by their
    ``<mesh inertia>`` (``legacy``, MuJoCo's default, ``convex``, ``exact``, ``shell``). A primitive
    with a ``mesh`` attribute is fitted to that mesh (its equivalent-inertia box, or its bounding box
    with ``<compiler fitaabb="true">``, times ``fitscale``). Attributes come through the ``<default>``
    classes and ``childclass`` as everywhere. A geom lighter than 1e-14 kg does not count. (Formulas:
    ``geom_inertia``.)
The body's
    The geoms merged exactly (parallel-axis theorem), then ``<compiler boundmass>`` and ``boundinertia``
    (lower bounds on the mass and on each principal moment of every body but the world, with or
    without geoms; a body with neither an inertial nor geom mass gets them, as in MuJoCo, at the point
    its own ``pos`` names, read in its own frame), ``balanceinertia`` (principal moments that break
    A + B >= C become their mean), and last ``settotalmass`` (every body's mass and inertia scaled so
    that they add up to it).

A ``plane`` carries no mass (MuJoCo allows one only on a static body); an ``hfield`` weighs as MuJoCo
weighs it, the box (x and y radii, elevation / 4 + base / 2) of its ``<hfield size>``; an ``sdf`` geom as
its mesh.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import PurePosixPath
from typing import Any, Callable, Mapping

import numpy as np

from ...bodies import Inertial
from ...compiled.conversions import pose_rows
from ...errors import InputError, quote
from .geom_inertia import MESH_INERTIA, PRIMITIVE_KINDS, mesh_mass, primitive_measure, primitive_moments
from .poses import Pose, geom_placement
from .source import MjcfSource
from ..trees.model import attribute_floats as _floats

__all__ = ["MassRules", "BodyMasses", "MeshUnavailable"]

#: MuJoCo's mjEPS: a geom lighter than this, or a primitive smaller than this, carries no mass
EPS = 1e-14
Attrs = Callable[[Any, str, str], Mapping[str, str]]


@dataclass(frozen=True)
class MassRules:
    """The ``<compiler>`` settings of mass (MuJoCo's defaults)."""

    inertiafromgeom: str = "auto"
    group_range: tuple[int, int] = (0, 5)
    boundmass: float = 0.0
    boundinertia: float = 0.0
    balanceinertia: bool = False
    settotalmass: float = -1.0
    fitaabb: bool = False

    @classmethod
    def of(cls, src: MjcfSource) -> "MassRules":
        kw: dict[str, Any] = {}
        for el in src.root.findall("compiler"):
            where = f"{src.source}: <compiler>"
            mode = el.get("inertiafromgeom")
            if mode is not None:
                if mode not in ("auto", "true", "false"):
                    raise InputError(f"{where}: inertiafromgeom {quote(mode)} is not one of auto, true, false")
                kw["inertiafromgeom"] = mode
            if el.get("inertiagrouprange") is not None:
                lo, hi = _floats(el.get("inertiagrouprange"), 2, f"{where} inertiagrouprange", ())
                kw["group_range"] = (int(lo), int(hi))
            for key in ("boundmass", "boundinertia", "settotalmass"):
                if el.get(key) is not None:
                    kw[key] = float(_floats(el.get(key), 1, f"{where} {key}", ())[0])
            for key in ("balanceinertia", "fitaabb"):
                value = el.get(key)
                if value is not None:
                    if value not in ("true", "false"):
                        raise InputError(f"{where}: {key} {quote(value)} is not true or false")
                    kw[key] = value == "true"
        return cls(**kw)


class MeshUnavailable(InputError):
    """A mesh whose mass cannot be had (no file for text input, not found, not readable, or a volume
    MuJoCo refuses)."""


def _int(text: str | None, default: int, where: str) -> int:
    try:
        return default if text is None else int(text.strip())
    except ValueError:
        raise InputError(f"{where}: '{text[:40]}' is not a whole number") from None


def _size(text: str | None, where: str) -> tuple[float, float, float]:
    """A geom's ``size``: one to three numbers, padded with 0."""
    parts = (text or "0").split()
    if not 1 <= len(parts) <= 3:
        raise InputError(f"{where}: '{(text or '')[:60]}' has {len(parts)} numbers; expected 1 to 3")
    s = [float(_floats(p, 1, where, ())[0]) for p in parts] + [0.0, 0.0]
    return s[0], s[1], s[2]


class _Mesh:
    """A mesh asset's mass per unit density (made on first use): measure, centre, inertia, and the
    principal frame and bounding box a fitted primitive needs."""

    def __init__(self, name: str, attrs: Mapping[str, str], src: MjcfSource, where: str):
        self.name, self.attrs, self.src, self.where = name, attrs, src, where
        self._mass: Any = None

    def points(self) -> tuple[np.ndarray, np.ndarray]:
        from .mesh_data import mesh_points, read_mesh_file, transformed

        a, where = self.attrs, self.where
        file = a.get("file")
        if file:
            from ..meshes.files import resolve_mesh_file

            if self.src.folder is None:
                raise MeshUnavailable(f"{where}: its file {quote(file)} cannot be found for MJCF given as text")
            rel = str(PurePosixPath(self.src.meshdir.replace("\\", "/")) / file.replace("\\", "/"))
            found = resolve_mesh_file(rel, self.src.source)
            if found.path is None:
                raise MeshUnavailable(f"{where}: {found.reason}")
            try:
                v, f = read_mesh_file(found.path, where)
            except (InputError, OSError) as exc:
                raise MeshUnavailable(str(exc) if isinstance(exc, InputError) else f"{where}: {exc}") from None
        else:
            v, f = mesh_points(a.get("vertex"), a.get("face"), where)
        scale = tuple(float(x) for x in _floats(a.get("scale"), 3, f"{where}: scale", (1, 1, 1)))
        refpos = tuple(float(x) for x in _floats(a.get("refpos"), 3, f"{where}: refpos", (0, 0, 0)))
        refquat = tuple(float(x) for x in _floats(a.get("refquat"), 4, f"{where}: refquat", (1, 0, 0, 0)))
        return transformed(v, f, scale, refpos, refquat)

    def mass(self) -> Any:
        if self._mass is None:
            mode = self.attrs.get("inertia", "legacy")
            if mode not in MESH_INERTIA:
                raise InputError(f"{self.where}: inertia {quote(mode)} is not one of {', '.join(MESH_INERTIA)}")
            v, f = self.points()
            try:
                mm = mesh_mass(v, f, mode, _int(self.attrs.get("maxhullvert"), -1, f"{self.where}: maxhullvert"))
            except ValueError as exc:  # MuJoCo refuses the model; robkin keeps its kinematics and shapes
                raise MeshUnavailable(f"{self.where}: {exc}") from None
            w, V = np.linalg.eigh(mm.inertia)
            w, V = w[::-1], V[:, ::-1] * np.array([1.0, 1.0, -1.0])  # MuJoCo's order: largest first
            mm.frame = V                              # principal axes (columns), a rotation
            mm.moments = w
            mm.box = 0.5 * np.sqrt(np.maximum(6 * (w.sum() - 2 * w) / mm.measure, 0.0))  # equivalent box
            local = (v - mm.centre) @ V
            mm.aabb = (local.min(axis=0), local.max(axis=0))
            self._mass = mm
        return self._mass


class BodyMasses:
    """Body name -> its ``Inertial`` (pose relative to the body frame) or None, by MuJoCo's rules."""

    def __init__(self, src: MjcfSource, attrs: Attrs, body_poses: Mapping[str, Pose] | None = None):
        self.src, self.attrs, self.body_poses = src, attrs, body_poses or {}
        self.rules = MassRules.of(src)
        self._meshes: dict[str, _Mesh] | None = None

    def meshes(self) -> dict[str, _Mesh]:
        if self._meshes is None:
            self._meshes = {}
            for asset in self.src.root.findall("asset"):
                for el in asset.findall("mesh"):
                    file = el.get("file")
                    name = el.get("name") or (PurePosixPath(file.replace("\\", "/")).stem if file else None)
                    if name:
                        where = f"{self.src.source}: mesh '{name}'"
                        self._meshes[name] = _Mesh(name, self.attrs(el, "main", where), self.src, where)
        return self._meshes

    def inertials(self, parts: Mapping[str, list[tuple[Any, Pose, str]]],
                  explicit: Mapping[str, Inertial]) -> dict[str, Inertial | None]:
        """Every body's inertial (``parts``: body -> its geoms and inertial, poses relative to the body;
        ``explicit``: the bodies' ``<inertial>``s as read)."""
        rules = self.rules
        out: dict[str, Inertial | None] = {}
        unavailable: list[str] = []
        for body, items in parts.items():
            if body == "world":
                out[body] = None
                continue
            given = explicit.get(body)
            if rules.inertiafromgeom == "true" or (rules.inertiafromgeom == "auto" and given is None):
                try:
                    geoms = [self._geom(el, T, cls, body, k) for k, (el, T, cls) in enumerate(items)
                             if el.tag == "geom"]
                except MeshUnavailable as exc:
                    unavailable.append(f"'{body}' ({exc})" if not unavailable else f"'{body}'")
                    out[body] = None
                    continue
                chosen = [g for g in geoms if g is not None and g[0] > EPS]
                if chosen:
                    given = self._merged(body, chosen)
            out[body] = self._bounded(body, given)
        if unavailable:
            import warnings

            listed = ", ".join(unavailable[:4]) + (f" and {len(unavailable) - 4} more" if len(unavailable) > 4 else "")
            warnings.warn(f"{self.src.source}: the mass MuJoCo gives {len(unavailable)} body(ies) from their mesh "
                          f"geoms cannot be computed, so they are left without mass properties: {listed}",
                          UserWarning, stacklevel=2)
        if rules.settotalmass > 0:
            total = sum(m.mass for m in out.values() if m is not None)
            if total > 0:
                s = rules.settotalmass / total
                out = {k: None if m is None else Inertial(m.link, m.body, m.pose, m.mass * s, m.inertia * s)
                       for k, m in out.items()}
        return out

    def _geom(self, el: Any, T: Pose, cls: str, body: str, k: int
              ) -> tuple[float, np.ndarray, np.ndarray] | None:
        """(mass, centre (3,), inertia (3, 3) about it, body-frame axes) of a geom in the inertia group
        range, or None."""
        name = el.get("name")
        where = f"{self.src.source}: geom '{name or f'#{k + 1}'}' (body '{body}')"
        a = self.attrs(el, cls, where)
        lo, hi = self.rules.group_range
        if not lo <= _int(a.get("group"), 0, f"{where}: group") <= hi:
            return None
        kind = a.get("type", "sphere")
        if kind == "plane":
            return None
        shell = a.get("shellinertia", "false")
        if shell not in ("true", "false"):
            raise InputError(f"{where}: shellinertia {quote(shell)} is not true or false")
        pose, length = geom_placement(a, self.src, where)
        P = pose_rows.matrix(pose_rows.compose(T, pose))
        mesh = a.get("mesh")
        if kind == "hfield":  # MuJoCo weighs a height field as the box (rx, ry, elevation / 4 + base / 2)
            kind, size = "box", self._hfield_size(a.get("hfield"), where)
        elif kind in ("mesh", "sdf") or (kind in PRIMITIVE_KINDS and mesh):
            if mesh not in self.meshes():
                raise InputError(f"{where}: mesh {quote(mesh)} is not a <mesh> of the <asset>s")
            mm = self.meshes()[mesh].mass()
            if kind in ("mesh", "sdf"):
                if shell == "true":
                    raise InputError(f"{where}: shellinertia on a mesh geom (MuJoCo refuses it: give the "
                                     f"<mesh> inertia=\"shell\")")
                measure, centre, unit = mm.measure, mm.centre, mm.inertia
                return self._massed(a, where, measure, lambda m: unit * (m / measure), P, centre)
            size, F = self._fitted(kind, mm, a, where)
            P = P @ F
        elif kind in PRIMITIVE_KINDS:
            size = _size(a.get("size"), f"{where}: size")
            if length is not None:
                size = (size[0], length / 2, 0.0) if kind in ("capsule", "cylinder") else (size[0], size[0], length / 2)
        else:
            raise InputError(f"{where}: type {quote(kind)} is not one of plane, hfield, {', '.join(PRIMITIVE_KINDS)}, "
                             f"mesh, sdf")
        if kind == "sphere":
            size = (size[0], 0.0, 0.0)
        sh = shell == "true"
        measure = primitive_measure(kind, size, sh)
        return self._massed(a, where, measure, lambda m: np.diag(primitive_moments(kind, size, m, sh)), P,
                            np.zeros(3))

    def _hfield_size(self, name: str | None, where: str) -> tuple[float, float, float]:
        for asset in self.src.root.findall("asset"):
            for el in asset.findall("hfield"):
                if el.get("name") == name:
                    rx, ry, ez, bz = _floats(el.get("size"), 4, f"{where}: hfield {quote(name)} size", ())
                    return float(rx), float(ry), 0.25 * float(ez) + 0.5 * float(bz)
        raise InputError(f"{where}: hfield {quote(name)} is not an <hfield> of the <asset>s")

    def _fitted(self, kind: str, mm: Any, a: Mapping[str, str], where: str
                ) -> tuple[tuple[float, float, float], np.ndarray]:
        """(MJCF size, pose (4, 4) in the mesh's coordinates) of a primitive fitted to a mesh (MuJoCo's
        ``FitGeom``: the mesh's equivalent-inertia box, or with ``fitaabb`` its bounding box in its
        principal frame, times ``fitscale``)."""
        b = mm.box
        centre = np.zeros(3)
        if kind == "ellipsoid" or kind == "box":
            size = b.copy()
        if not self.rules.fitaabb:
            if kind == "sphere":
                size = np.array([b.sum() / 3, 0.0, 0.0])
            elif kind == "capsule":
                r = (b[0] + b[1]) / 2
                size = np.array([r, max(0.0, b[2] - r / 2), 0.0])
            elif kind == "cylinder":
                size = np.array([(b[0] + b[1]) / 2, b[2], 0.0])
        else:
            lo, hi = mm.aabb
            centre = (lo + hi) / 2
            half = hi - centre
            if kind in ("ellipsoid", "box"):
                size = half
            elif kind == "sphere":
                size = np.array([half.max(), 0.0, 0.0])
            else:
                r = max(half[0], half[1])
                size = np.array([r, half[2] - (r if kind == "capsule" else 0.0), 0.0])
        scale = float(_floats(a.get("fitscale"), 1, f"{where}: fitscale", (1.0,))[0])
        F = np.eye(4)
        F[:3, :3] = mm.frame
        F[:3, 3] = mm.centre + mm.frame @ centre
        return (float(size[0] * scale), float(size[1] * scale), float(size[2] * scale)), F

    def _massed(self, a: Mapping[str, str], where: str, measure: float, inertia: Callable[[float], np.ndarray],
                P: np.ndarray, centre: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """(mass, centre, inertia) in the body frame of a geom of ``measure``, its inertia (geom axes) for
        a mass, placed at ``P`` (4, 4) with its centre at ``centre`` (geom frame)."""
        if a.get("mass") is not None:
            given = float(_floats(a.get("mass"), 1, f"{where}: mass", ())[0])
            mass = given if given != 0 and measure > EPS else 0.0
        else:
            density = float(_floats(a.get("density"), 1, f"{where}: density", (1000.0,))[0])
            mass = density * measure
        if mass < 0:
            raise InputError(f"{where}: mass or density is negative (MuJoCo refuses it)")
        R = P[:3, :3]
        I = R @ inertia(mass) @ R.T if mass > 0 else np.zeros((3, 3))
        return mass, R @ centre + P[:3, 3], I

    @staticmethod
    def _merged(body: str, chosen: list[tuple[float, np.ndarray, np.ndarray]]) -> Inertial:
        from ...mass_properties import merge_masses

        if len(chosen) == 1:
            m, c, I = chosen[0]
        else:
            m, c, I = merge_masses(np.array([g[0] for g in chosen]), np.stack([g[1] for g in chosen]),
                                   np.stack([g[2] for g in chosen]))
        pose = np.eye(4)
        pose[:3, 3] = c
        return Inertial(body, 0, pose, float(m), 0.5 * (I + I.T))

    def _bounded(self, body: str, m: Inertial | None) -> Inertial | None:
        """``m`` with boundmass, boundinertia and balanceinertia applied (principal moments)."""
        r = self.rules
        if r.boundmass <= 0 and r.boundinertia <= 0 and not r.balanceinertia:
            return m
        pose = np.eye(4) if m is None else m.pose
        if m is None:
            # MuJoCo's: a body without an inertial frame takes its own pos and orientation (relative to
            # its parent) as one, read relative to itself
            own = self.body_poses.get(body)
            pose = np.eye(4) if own is None else pose_rows.matrix(own)
        mass = 0.0 if m is None else m.mass
        I = np.zeros((3, 3)) if m is None else pose[:3, :3] @ m.inertia @ pose[:3, :3].T
        w, V = np.linalg.eigh(I)
        w2 = np.maximum(w, r.boundinertia)
        if r.balanceinertia and any(w2[i] + w2[j] < w2[k] for i, j, k in ((0, 1, 2), (0, 2, 1), (1, 2, 0))):
            w2 = np.full(3, w2.sum() / 3)
        mass2 = max(mass, r.boundmass)
        if (m is not None and mass2 == mass and np.array_equal(w2, w)) or (mass2 == 0 and not w2.any()):
            return m
        if m is None:  # principal moments in the body's own orientation (MuJoCo's quirk above)
            return Inertial(body, 0, pose, mass2, np.diag(w2))
        centre = np.eye(4)
        centre[:3, 3] = pose[:3, 3]
        return Inertial(body, 0, centre, mass2, V @ np.diag(w2) @ V.T, m.origin)
