"""robkin check MODEL MEASUREMENTS: the command-line side of ``robkin.calibration.diagnosis``."""

from __future__ import annotations

import argparse
import math


def run_measurements(args: argparse.Namespace) -> int:
    """Compare the model (args.a) with the measurements (args.b); exit 0 if it explains them within --tol.

    A model whose joints carry a ``stiffness`` (a compliance calibration's) is compared deflected by the
    gravity torques of the measurements' ``payload`` column (at the tool origin or ``--payload-com``)."""
    from ...calibration.diagnosis import DEFAULT_TOL, diagnose
    from ...calibration.measurements import read_measurements
    from ...errors import InputError
    from ...io import load
    from .chains import chain_ends
    from .output import print_json

    tol = DEFAULT_TOL if args.tol is None else args.tol
    if not (math.isfinite(tol) and tol > 0):
        raise InputError(f"--tol: {tol} is not a positive number of metres")
    (base, tip), _ = chain_ends(args, [args.a, args.b])
    robot = load(args.a, base_link=base, tip_link=tip, allow_xacro=args.allow_xacro)
    m = read_measurements(args.b, robot)
    q = m.q
    if m.payloads is not None and any(j.stiffness for j in robot.joints):   # the model's compliance applies
        from dataclasses import replace

        from ...calibration.compliance import compliant_q
        from .common import parse_q

        com = None if args.payload_com is None else parse_q(args.payload_com, 3, "--payload-com")
        q = compliant_q(robot, m.q, m.payloads, com)
        m = replace(m, q=q)
    if args.report:   # ISO 9283 figures or the HTML report instead of the diagnosis text
        from .measurement_reports import run_report

        return run_report(args, robot, m, tol)
    result = diagnose(robot, q, m.positions, m.quaternions, tol=tol, rows=m.rows)
    if args.json:
        d = result.to_dict()
        d["model"], d["measurements"] = args.a, args.b
        print_json(d)
    else:
        print(result.text())
    return 0 if result.same else 1
