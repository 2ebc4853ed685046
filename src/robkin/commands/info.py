"""robkin info: a robot's joints (types, limits, axes) and how each axis relates to the one before."""

from __future__ import annotations

import argparse
import math

from .support.common import add_input, load_input

EPILOG = """\
For each joint: type, limits, the axis direction and a point on it (in the robot base frame at q = 0),
and how the axis relates to the previous one (the base z axis for joint 1): skew, parallel,
anti-parallel, coincident, anti-coincident or intersecting, with the angle and distance between them.
A prismatic joint is a direction, not a line: next to one, only parallel / anti-parallel / not
parallel and the angle are given.

A URDF, MJCF or SDF file that is a tree (several chains end below the base) and no --tip-link: the
chains it offers are listed instead (tip link, number of joints, joint types, first and last joint),
to pick one with --tip-link.

examples:
  robkin info rrpr.yaml
  robkin info panda.urdf --tip-link panda_hand_tcp
  robkin info ur5.urdf --tip-link tool0 --json
  robkin info panda.urdf                                   # a tree: lists the chains it offers
"""


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser("info", help="joint table: types, limits, axes and how they relate",
                       description="Describe a robot: joints, types, limits, axis directions and the relation "
                                   "of each axis to the previous one.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_input(p)
    p.add_argument("--json", action="store_true", help="print the description as JSON")
    return p


def describe(robot) -> dict:
    """JSON-ready description of a robot: joints with axes and relations, tool and world poses."""
    import numpy as np

    from .. import se3
    from ..lines import ANGLE_TOL, classify, common_normal

    z_prev, p_prev, line_prev = np.array([0.0, 0.0, 1.0]), np.zeros(3), True
    joints = []
    for i, j in enumerate(robot.joints):
        z, p = robot.axes[i], robot.points[i]
        if j.revolute:
            p = p - np.dot(p, z) * z  # the point of the axis closest to the base origin
        angle = math.degrees(math.acos(float(np.clip(np.dot(z_prev, z), -1.0, 1.0))))
        dist: float | None = None
        if j.revolute and line_prev:
            rel = classify(p_prev, z_prev, p, z, robot.scale).value
            dist = _c(common_normal(p_prev, z_prev, p, z).distance)
        else:
            # a prismatic joint is a direction: only the angle between the axes means something
            sin = float(np.linalg.norm(np.cross(z_prev, z)))
            rel = ("parallel" if np.dot(z_prev, z) > 0 else "anti-parallel") if sin < ANGLE_TOL else "not parallel"
        joints.append({"index": i + 1, "name": j.name, "type": j.type,
                       "lower": j.lower, "upper": j.upper, "flip": j.flip,
                       "axis": _clean(z), "point": _clean(p) if j.revolute else None, "relation": rel,
                       "angle_deg": _c(angle), "distance": dist})
        z_prev, p_prev, line_prev = z, p, j.revolute
    tool = robot.tool
    return {"name": robot.name, "n": robot.n, "types": "".join("R" if j.revolute else "P" for j in robot.joints),
            "scale": robot.scale, "joints": joints,
            "tool": {"position": _clean(tool[:3, 3]), "rpy": _clean(se3.rpy_from_matrix(tool[:3, :3])),
                     "matrix": [_clean(r) for r in tool]},
            "world": [_clean(r) for r in robot.world]}


def _c(x: float) -> float:
    # below 1e-12 is rounding noise of products (robot sizes ~1e-3..1e3): print an exact 0
    return 0.0 if abs(x) < 1e-12 else float(x)


def _clean(v) -> list[float]:
    return [_c(x) for x in v]


def _tree_chains(args: argparse.Namespace):
    """(tree, chains): the input's tree (see ``io.chain_path.tree_of_file``; None for a document or a
    .xacro) and, when no --tip-link picks one of several chains it offers, those chains (else None)."""
    from ..io import tree_of_file

    tree = tree_of_file(args.input)
    if tree is None or args.tip_link:
        return tree, None
    from ..io.urdf.chain import chains_of

    chains = chains_of(tree[0], args.base_link)
    return tree, (chains if len(chains) > 1 else None)


def _show_chains(path: str, chains, kinds: dict[str, str], as_json: bool) -> int:
    """The chains a tree offers; ``kinds`` names the joints that make no chain (MJCF ball/free...)."""
    items = [{"base": base, "tip": tip, "n": len(js), "types": "".join("P" if j.type == "prismatic" else "R"
                                                                       for j in js),
              "joints": [j.name for j in js], "mimic": [j.name for j in js if j.mimic],
              "unsupported": [j.name for j in js if j.name in kinds]}
             for base, tip, js in chains]
    if as_json:
        from .support.output import print_json

        print_json({"file": path, "tree": True, "chains": items})
        return 0
    from ..io.tables.terminal import show_blocks

    def note(c) -> str:
        if c["unsupported"]:
            return f"{kinds[c['unsupported'][0]]} joint {c['unsupported'][0]}: no chain through it"
        return f"mimic joint {c['mimic'][0]}: end before it" if c["mimic"] else ""

    rows = [[c["tip"], str(c["n"]), c["types"], c["joints"][0] if c["joints"] else "-",
             c["joints"][-1] if c["joints"] else "-", note(c)] for c in items]
    show_blocks([(f"{path}: a tree; {len(items)} chains from '{items[0]['base']}' (pick one with --tip-link)",
                  ["tip link", "joints", "types", "first joint", "last joint", "note"], rows)])
    return 0


def run(args: argparse.Namespace) -> int:
    tree, chains = _tree_chains(args)
    if chains is not None:
        return _show_chains(args.input, chains, tree[1], args.json)
    if tree is not None:
        from ..io.trees.chain_path import refuse_on_chain
        from ..io.urdf import robot_from_model

        model, kinds, supported = tree
        refuse_on_chain(model, kinds, args.base_link, args.tip_link, supported)
        robot = robot_from_model(model, args.base_link, args.tip_link)
    else:
        robot = load_input(args.input, args)
    d = describe(robot)
    if args.json:
        from .support.output import print_json

        print_json(d)
        return 0
    import numpy as np

    from ..io.tables.terminal import fmt_num, matrix_text, show_blocks

    def lim(x):
        return "-" if x is None else fmt_num(x)

    def vec(v):
        return " ".join(fmt_num(x, 4) for x in v)

    rows = [[str(j["index"]), j["name"], j["type"] + (" (flip)" if j["flip"] else ""), lim(j["lower"]),
             lim(j["upper"]), vec(j["axis"]), vec(j["point"]) if j["type"] == "revolute" else "(direction only)",
             j["relation"], j["angle_deg"], "-" if j["distance"] is None else j["distance"]]
            for j in d["joints"]]
    title = (f"{robot.name or args.input}: {robot.n} joints ({d['types']}); axes in the base frame at q = 0, "
             f"relation to the previous axis (joint 1: base z)")
    items = [(title, ["i", "joint", "type", "lower", "upper", "axis", "point on axis (m)", "relation",
                      "angle deg", "distance m"], rows),
             "tool at q = 0: position " + vec(d["tool"]["position"]) + " m, rpy " + vec(d["tool"]["rpy"]) + " rad",
             f"size: {fmt_num(robot.scale, 4)} m (the largest distance of a joint axis or of the tool from the base "
             f"origin; relative tolerances are fractions of it); limits in rad (revolute) and m (prismatic)"]
    if not np.allclose(robot.world, np.eye(4), atol=1e-12, rtol=0):
        items.append(matrix_text(robot.world, "world -> base"))
    show_blocks(items)
    return 0
