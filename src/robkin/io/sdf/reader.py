"""SDF (SDFormat 1.4+, Gazebo's XML) input: the links and joints of a model as a Robot.

What is read
    ``<link>``, ``<joint>`` (revolute, continuous, prismatic, fixed), explicit ``<frame>``s and
    nested ``<model>``s (their names scoped as ``inner::link``), each ``<pose>`` with ``relative_to``
    (SDFormat 1.8; also ``degrees`` and ``rotation_format="quat_xyzw"`` of 1.9), joint axes
    ``<axis><xyz expressed_in>`` with ``<limit><lower><upper>``; visuals, collisions and inertials as
    ``Robot.bodies`` (see ``shapes``). Sensors and plugins are ignored; ``<include>`` (a model from
    a URI) is refused.

Default frames (every version)
    a link's or nested model's pose is in its model frame; a joint's pose is in its child link's
    frame; an explicit frame's pose is in the frame it is attached to. A joint axis is in the joint
    frame from 1.5 on (unless ``use_parent_model_frame`` is true or ``expressed_in`` names another
    frame) and in the model frame in 1.4.

The tree becomes a ``UrdfModel`` whose links are the SDF links and frames (a joint whose frame is not
its child link's frame gets an intermediate link ``CHILD@JOINT``) and the chain is picked by the URDF
reader's ``robot_from_model``. q is the SDF joint position (same sign and zero); a joint whose parent
is ``world`` fixes the model in the world (``Robot.world``). Other joint kinds (ball, universal,
screw...) on the chosen chain are refused with one line naming the joint.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

from ...compiled.conversions import pose_rows
from ...errors import InputError, quote
from ...robot import Robot
from ..trees.chain_path import refuse_on_chain
from ..files.input_files import read_text_file
from .axes import Z_AXIS, axis_dynamics, joint_axis
from .frame_graph import IDENTITY, FrameGraph, element_pose, sdf_version, the_models
from ..urdf.chain import robot_from_model
from ..trees.model import UrdfJoint, UrdfModel

if TYPE_CHECKING:  # pragma: no cover
    from ...compiled.conversions.pose_rows import Pose  # twelve floats: the top three rows of a (4, 4) pose
else:
    Pose = tuple

__all__ = ["robot_from_sdf", "model_from_sdf"]

#: Largest SDF read (world files with many models are a few MB; this stops huge inputs).
MAX_BYTES = 64 * 1024 * 1024
JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed")
OTHER_JOINTS = ("ball", "universal", "revolute2", "screw", "gearbox")
#: The joint kinds that make a serial chain, as messages word them.
CHAIN_JOINTS = "revolute, continuous, prismatic and fixed"


def model_from_sdf(source: str | os.PathLike[str]) -> tuple[UrdfModel, dict[str, str]]:
    """The kinematic tree of an SDF file (path) or SDF text, and the joints robkin cannot model."""
    from ...compiled.scanners.sdf_scan import kinematic_tree
    from .shapes import sdf_content
    from .trees import check_tree
    from ..trees.xml_parse import _refuse_dtd

    folder = None
    if isinstance(source, str) and source.lstrip().startswith("<"):
        text, src = source, "<sdf string>"
    else:
        text, src, folder = read_text_file(Path(source), MAX_BYTES, "an SDF model"), str(source), Path(source).parent
        if not text.strip():
            raise InputError(f"{src}: file is empty; expected an SDF <sdf> element")
    _refuse_dtd(text, src)
    root = kinematic_tree(text, src)  # only the elements read here; sdf_content parses the rest when asked
    if root.tag != "sdf":
        raise InputError(f"{src}: root element is <{root.tag}>; an SDF file has <sdf>")
    version = sdf_version(root, src)
    models = the_models(root)
    if len(models) != 1:
        raise InputError(f"{src}: holds {len(models)} <model> elements; robkin reads a file with one model")
    j = FrameGraph(src, version)
    j.read(models[0], "", 0)
    # the model's pose in the world; used when a joint fixes the model to the world
    world = element_pose(models[0], f"{src}: model")[0]
    links = list(j.links) + [name for name in j.attached]
    joints: list[UrdfJoint] = []
    kinds: dict[str, str] = {}
    uses_world = False
    for name, el, prefix in j.joints:
        where = f"{src}: joint '{name}'"
        jtype = el.get("type")
        if jtype not in JOINT_TYPES and jtype not in OTHER_JOINTS:
            raise InputError(f"{where}: type {quote(jtype)} is not one of {', '.join(JOINT_TYPES + OTHER_JOINTS)}")
        parent = j.scoped(j._text(el, "parent", name), prefix)
        child = j.child_of.get(el) or j.scoped(j._text(el, "child", name), prefix)
        if parent != "world" and j.kind.get(parent) != "link":
            raise InputError(f"{where}: parent {quote(parent)} is not a link of the model")
        if child != "world" and j.kind.get(child) != "link":
            raise InputError(f"{where}: child {quote(child)} is not a link of the model")
        # the joint frame in the parent link's (the world's: the model's pose in it)
        origin = pose_rows.compose(world, j.pose(name, where)) if parent == "world" else \
            j.relative(parent, name, where)
        uses_world |= parent == "world"
        # joint frame -> child link frame; exactly the identity when the joint's pose is the default
        rest = j.relative(name, child, where)
        moving = jtype if jtype in JOINT_TYPES else "floating"
        axis_el = el.find("axis")
        axis, lower, upper = (Z_AXIS, None, None) if jtype == "fixed" or moving == "floating" \
            else joint_axis(j, axis_el, name, where)
        if moving == "floating":
            kinds[name] = jtype
        if moving == "revolute" and lower is None and upper is None:
            moving = "continuous"
        # the joint moves the joint frame; the child link hangs off it (directly when the frames coincide)
        exact = rest == IDENTITY
        mid = child if exact else f"{child}@{name}"
        if not exact:
            links.append(mid)
        effort, velocity, damping, friction = (axis_dynamics(axis_el, where)
                                               if moving != "floating" else (None, None, None, None))
        joints.append(UrdfJoint(name, moving, parent, mid, None, axis, lower, upper, None, effort=effort,
                                velocity=velocity, damping=damping, friction=friction, pose=origin))
        if not exact:
            joints.append(UrdfJoint(f"{name}:child", "fixed", mid, child, None, Z_AXIS, None, None, None, pose=rest))
    for name, attached in j.attached.items():
        base = attached
        while j.kind.get(base) == "frame":
            base = j.attached[base]
        if base == "__model__":  # the model frame is fixed to the canonical link
            base = models[0].get("canonical_link") or (j.links[0] if j.links else "")
        base = j.joint_child.get(base, base)  # a joint frame moves with its child link
        if j.kind.get(base) != "link":
            raise InputError(f"{src}: frame '{name}' is attached to '{attached}', which is not a link, joint or "
                             f"frame of the model's top level; attach it to a link (attached_to=\"LINK\")")
        joints.append(UrdfJoint(f"{name}:frame", "fixed", base, name, None, Z_AXIS, None, None, None,
                                pose=j.relative(base, name, src)))
    if uses_world:
        links.insert(0, "world")
    model = UrdfModel(models[0].get("name"), tuple(links), tuple(joints), src, sdf_content(j, folder, text))
    check_tree(model)
    return model, kinds


def robot_from_sdf(source: str | os.PathLike[str], base_link: str | None = None, tip_link: str | None = None,
                   *, name: str | None = None) -> Robot:
    """The serial chain base_link -> tip_link of an SDF model as a Robot (q = the SDF joint positions).

    Parameters
    ----------
    source : path or str
        A .sdf file, or SDF text (a string starting with '<').
    base_link, tip_link : str, optional
        Links or explicit frames at the chain's ends (nested models' as ``inner::link``). Default base:
        the root link (the link fixed to ``world`` when a joint does that); default tip: the only leaf.
        A model whose links form several unconnected trees: the tree holding these links, or the
        only one with moving joints (see ``trees``).
    name : str, optional
        Robot name; default the model's name.

    Returns
    -------
    Robot
        GJD frames (n+1, 4, 4) in the base link frame, joints with the SDF names and limits
        (radians, metres); ``world`` = world -> base at q = 0 when the model is fixed to the world.
    """
    from .trees import pick_tree

    model, kinds = model_from_sdf(source)
    model = pick_tree(model, base_link, tip_link)  # a model may hold several unconnected trees
    refuse_on_chain(model, kinds, base_link, tip_link, CHAIN_JOINTS)
    return robot_from_model(model, base_link, tip_link, name=name)
