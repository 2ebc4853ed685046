"""robkin demo: the conversion paper's examples through every representation."""

from __future__ import annotations

import argparse

import numpy as np

from ..examples import EXAMPLES_DIR

EXAMPLES = ("rrpr.yaml", "arbitrary_3r.yaml")
DEMO_Q = {"rrpr": [3 * np.pi / 4, -np.pi / 4, 0.3, -3 * np.pi / 4]}


EPILOG = """\
The 3R robot's numbers were printed with 3 decimals in the paper: expect warnings that its M and
screws were projected onto the nearest valid values.

examples:
  robkin demo
  robkin demo | less
  robkin convert {examples}/rrpr.yaml --to poe     # one of the demo's robots, one representation
"""


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    return sub.add_parser("demo", help="show the paper's examples in every representation",
                          description="Convert the conversion paper's RRPR and arbitrary 3R robots (bundled "
                                      f"in {EXAMPLES_DIR}) into every representation and check that forward "
                                      "kinematics agrees.",
                          epilog=EPILOG.format(examples=EXAMPLES_DIR),
                          formatter_class=argparse.RawDescriptionHelpFormatter)


def run(args: argparse.Namespace) -> int:
    from ..io.documents.reader import read_document
    from ..io.tables.terminal import FORMATS, render
    from ..representations import dh_from_robot, mdh_from_robot, poe_from_robot, rpy_from_robot

    rule = "=" * 78
    for name in EXAMPLES:
        path = EXAMPLES_DIR / name
        robot = read_document(path)
        print(f"{rule}\n{robot.name}  ({path})\n{rule}")
        for fmt in FORMATS:
            print(render(robot, fmt, layout="paper") + "\n")
        q = np.array(DEMO_Q.get(robot.name or "", robot.random_q(rng=7)))
        reps = {"GJD": robot, "DH": dh_from_robot(robot), "MDH": mdh_from_robot(robot),
                "PoE space": poe_from_robot(robot), "PoE body": poe_from_robot(robot, "body"),
                "RPY-XYZ": rpy_from_robot(robot), "DH via PoE": dh_from_robot(poe_from_robot(robot).to_robot())}
        T = robot.fk(q)
        worst = max(float(np.abs(rep.fk(q) - T).max()) for rep in reps.values())
        print(f"FK at q = [{', '.join(f'{v:.4g}' for v in q)}] agrees across {', '.join(reps)}: "
              f"largest difference {worst:.1e}\n")
    return 0
