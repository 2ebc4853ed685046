"""The frame graph of an SDF model: its (nested) models, links, joints and frames, their ``<pose>``s and
``relative_to`` references resolved into poses of the model frame (SDFormat 1.4+ semantics).

Built by the reader (``reader.model_from_sdf``) and used by it, by ``axes`` (a joint axis's
``expressed_in`` frame) and by ``shapes`` (the poses of visuals, collisions and inertials).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from ...compiled.conversions import pose_rows
from ...compiled.scanners.attribute_numbers import numbers
from ...errors import InputError, quote

if TYPE_CHECKING:  # pragma: no cover
    from ...compiled.conversions.pose_rows import Pose  # twelve floats: the top three rows of a (4, 4) pose
else:
    Pose = tuple

__all__ = ["FrameGraph", "the_models", "sdf_version", "element_pose", "IDENTITY", "MAX_NESTING", "NEAR_STEPS"]

#: Nested models deeper than this are refused (real files nest one or two levels).
MAX_NESTING = 16
#: The pose of one frame in another is composed through their nearest common frame of the relative_to
#: graph when that is at most this many steps away (a joint next to its links: 1-3), from the file's own
#: numbers; farther, through the model frame (poses of frames deep in a chain of relative_to carry the
#: rounding of every pose above them, ~1e-16 per step: a 1000-link chain's frames were then no longer
#: rigid to 1e-12). A bound keeps each lookup O(1).
NEAR_STEPS = 8
IDENTITY = pose_rows.IDENTITY
INVERSE_IDENTITY = pose_rows.inverse(IDENTITY)  # the same floats inverse() gives each time, made once
ZEROS6 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def the_models(root: Any) -> list[Any]:
    """The ``<model>`` elements of an SDF root: its own, else those of its ``<world>``s."""
    return root.findall("model") or [m for w in root.findall("world") for m in w.findall("model")]


def sdf_version(root: Any, source: str) -> tuple[int, int]:
    text = root.get("version")
    if text is None:
        raise InputError(f"{source}: <sdf> has no version attribute; expected e.g. version=\"1.9\"")
    try:
        major, minor = (int(x) for x in text.split("."))
    except ValueError:
        raise InputError(f"{source}: <sdf version=\"{text}\"> is not a version such as 1.9") from None
    if (major, minor) < (1, 4):
        raise InputError(f"{source}: SDFormat {text} is not read; robkin reads SDFormat 1.4 and later")
    return major, minor


def element_pose(el: Any, where: str) -> tuple[Pose, str | None]:
    """(pose (twelve floats, see ``pose_rows``), relative_to or None) of an element's ``<pose>`` child
    (identity when absent)."""
    pose = el.find("pose")
    if pose is None:
        return IDENTITY, None
    text = pose.text
    text = (text.strip() or None) if text else None
    form = pose.get("rotation_format", "euler_rpy")
    if form == "euler_rpy":
        if text is None:  # from_xyz_rpy of six zeros: exactly these floats (its exact branch)
            return IDENTITY, pose.get("relative_to") or None
        v = numbers(text, 6, where, "<pose>", ZEROS6)
        rpy = tuple(math.radians(a) for a in v[3:]) if pose.get("degrees") == "true" else v[3:]
        return pose_rows.from_xyz_rpy(v[:3], rpy), pose.get("relative_to") or None
    at = f"{where}: <pose>"
    if form == "quat_xyzw":
        v = numbers(text, 7, at, None, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0))
        if math.hypot(*v[3:]) < 1e-10:  # a quaternion this short is a typo; unit quaternions have length 1
            raise InputError(f"{at}: quaternion is zero")
        return pose_rows.from_quat(v[:3], (v[6], v[3], v[4], v[5])), pose.get("relative_to") or None
    raise InputError(f"{at}: rotation_format {quote(pose.get('rotation_format'))} is not euler_rpy or quat_xyzw")


class FrameGraph:
    """The frames of one model file, flattened over nested models, resolved to the outer model frame."""

    def __init__(self, source: str, version: tuple[int, int]):
        self.source = source
        self.version = version
        self.raw: dict[str, tuple[Pose, str]] = {}  # frame -> (pose, frame it is relative to)
        self.kind: dict[str, str] = {}                       # frame -> link | joint | frame | model
        self.attached: dict[str, str] = {}                   # explicit frame -> frame it is attached to
        self.links: list[str] = []
        self.joints: list[tuple[str, Any, str]] = []         # (scoped name, element, scope prefix)
        self.resolved: dict[str, Pose] = {}
        self.up: dict[str, str] = {}     # frame -> the frame its pose is relative to (nested models: X::__model__)
        self.depth: dict[str, int] = {}  # frame -> steps of relative_to from it to the model frame
        self.joint_child: dict[str, str] = {}                # joint -> its child link
        self.child_of: dict[Any, str] = {}                   # <joint> element read above -> its child link
        self.link_elements: list[tuple[str, Any, str]] = []  # (scoped link name, <link>, scope prefix)

    def _frame(self, name: str, kind: str, pose: Pose, rel: str) -> None:
        if name in self.kind:
            raise InputError(f"{self.source}: two {self.kind[name]}/{kind} elements are called '{name}'")
        self.kind[name] = kind
        self.raw[name] = (pose, rel)

    def read(self, model: Any, prefix: str, depth: int) -> None:
        if depth > MAX_NESTING:
            raise InputError(f"{self.source}: models nest more than {MAX_NESTING} levels deep")
        scope = prefix + "__model__"
        if model.find("include") is not None:
            raise InputError(f"{self.source}: model '{prefix}{model.get('name')}': <include> (a model from a URI) is "
                             f"not read; merge the included model into the file")
        for tag in ("link", "frame", "model", "joint"):
            for i, el in enumerate(model.findall(tag)):
                local = el.get("name")
                if not local:
                    raise InputError(f"{self.source}: <{tag}> #{i + 1} of model '{prefix or model.get('name')}' "
                                     f"has no name attribute")
                name = prefix + local
                if tag == "joint":
                    self.joints.append((name, el, prefix))
                    continue  # its frame (by default its child link's) is registered below, after the links
                pose, rel = element_pose(el, f"{self.source}: {tag} '{name}'")
                if tag == "frame":
                    attached = self.scoped(el.get("attached_to") or "__model__", prefix)
                    self.attached[name] = attached
                    self._frame(name, "frame", pose, self.scoped(rel, prefix) if rel else attached)
                elif tag == "link":
                    self.links.append(name)
                    self.link_elements.append((name, el, prefix))
                    self._frame(name, "link", pose, self.scoped(rel, prefix) if rel else scope)
                else:
                    self._frame(name + "::__model__", "model", pose, self.scoped(rel, prefix) if rel else scope)
                    self.read(el, name + "::", depth + 1)
        for name, el, p in self.joints:
            if p == prefix and name not in self.kind:
                child = self.scoped(self._text(el, "child", name), prefix)
                self.joint_child[name] = self.child_of[el] = child
                pose, rel = element_pose(el, f"{self.source}: joint '{name}'")
                self._frame(name, "joint", pose, self.scoped(rel, prefix) if rel else child)

    def _text(self, el: Any, tag: str, name: str) -> str:
        sub = el.find(tag)
        text = (sub.text or "").strip() if sub is not None else ""
        if not text:
            raise InputError(f"{self.source}: joint '{name}': missing <{tag}>LINK</{tag}>")
        return text

    @staticmethod
    def scoped(name: str, prefix: str) -> str:
        return name if name == "world" else prefix + name

    def _depth(self, name: str, where: str) -> int:
        """Steps of relative_to from frame ``name`` to the model frame, filling ``up`` and ``depth`` along
        the way (InputError for a frame the file does not have, or a loop)."""
        raw = self.raw.get(name) if name != "__model__" else None
        if raw is not None:  # relative_to a frame already resolved (keys of depth are names of raw)
            rel = raw[1]
            d = 0 if rel == "__model__" else self.depth.get(rel)
            if d is not None and rel != name:
                self.depth[name], self.up[name] = d + 1, rel
                return d + 1
        chain, seen = [], set()
        while name != "__model__" and name not in self.depth:
            if name not in self.raw and name + "::__model__" in self.raw:
                name += "::__model__"  # a nested model's name stands for its model frame
            if name not in self.raw:
                raise InputError(f"{where}: frame {quote(name)} is not a link, joint, frame or model of the file")
            if name in seen:
                raise InputError(f"{where}: the poses' relative_to form a loop through '{name}'")
            seen.add(name)
            chain.append(name)
            name = self.raw[name][1]
        depth = 0 if name == "__model__" else self.depth[name]
        for n in reversed(chain):
            depth += 1
            self.depth[n], self.up[n], name = depth, name, n
        return depth

    def pose(self, name: str, where: str) -> Pose:
        """Pose of frame ``name`` in the outermost model frame (q = 0), as twelve floats: the poses
        along its relative_to path composed from the model frame down, each made once."""
        T = self.resolved.get(name)
        if T is not None:
            return T
        self._depth(name, where)
        chain = []
        while name != "__model__" and name not in self.resolved:
            name = name if name in self.raw else name + "::__model__"  # _depth has checked the names
            chain.append(name)
            name = self.up[name]
        T = IDENTITY if name == "__model__" else self.resolved[name]
        for n in reversed(chain):
            T = self.resolved[n] = pose_rows.compose(T, self.raw[n][0])
        return T

    def relative(self, a: str, b: str, where: str) -> Pose:
        """Pose of frame ``b`` in frame ``a`` (q = 0): through their nearest common frame when that is
        at most ``NEAR_STEPS`` away (see there), else through the model frame."""
        depth, up, raw = self.depth, self.up, self.raw
        da = depth.get(a)
        if da is None:
            da = self._depth(a, where)
        db = depth.get(b)
        if db is None:
            db = self._depth(b, where)
        # one frame relative_to the other (a joint and its links): the walk below in one step
        if up.get(b) == a:
            return pose_rows.compose(INVERSE_IDENTITY, pose_rows.compose(raw[b][0], IDENTITY))
        if up.get(a) == b:
            return pose_rows.compose(pose_rows.inverse(pose_rows.compose(raw[a][0], IDENTITY)), IDENTITY)
        a0, b0 = a, b
        a = a if a == "__model__" or a in raw else a + "::__model__"  # _depth has checked the names
        b = b if b == "__model__" or b in raw else b + "::__model__"
        A = B = IDENTITY  # poses of the given a and b in the frames a and b have walked up to
        for _ in range(NEAR_STEPS):
            if a == b:
                return pose_rows.compose(INVERSE_IDENTITY if A is IDENTITY else pose_rows.inverse(A), B)
            if da >= db:
                A, a, da = pose_rows.compose(raw[a][0], A), up[a], da - 1
            else:
                B, b, db = pose_rows.compose(raw[b][0], B), up[b], db - 1
        return pose_rows.compose(pose_rows.inverse(self.pose(a0, where)), self.pose(b0, where))
