"""robkin check MODEL MEASUREMENTS --report iso9283 | html: the measurement reports' command-line side.

- ``iso9283``: ISO 9283 pose accuracy AP and repeatability RP per commanded pose
  (``robkin.calibration.iso9283``), as text or ``--json``.
- ``html`` (``-o REPORT.html``): one self-contained page (``robkin.viz.report_html``) with the
  diagnosis, the ISO 9283 table and residual plots per pose and per joint (``robkin.viz.residual_plots``,
  matplotlib).

The exit status keeps ``check``'s meaning: 0 if the model with its best base and marker explains the
measurements within --tol (RMS position residual), 1 if not; 2 on bad input (nothing written).
"""

from __future__ import annotations

import argparse

REPORTS = ("iso9283", "html")


def add_report_options(p: argparse.ArgumentParser) -> None:
    """--report and -o of ``robkin check``."""
    p.add_argument("--report", choices=REPORTS,
                   help="against measurements: iso9283 (ISO 9283 pose accuracy AP and repeatability RP per "
                        "commanded pose: rows with equal joint values) or html (-o REPORT.html: diagnosis, "
                        "ISO 9283 table, residual plots per pose and per joint; needs matplotlib)")
    p.add_argument("-o", "--output", metavar="REPORT.html", help="the file --report html writes")


def check_report_options(args: argparse.Namespace, measurements: bool) -> None:
    """InputError for --report / -o where they do not apply."""
    from ...errors import InputError

    if not measurements and (args.report or args.output):
        raise InputError(f"{'--report' if args.report else '-o'}: applies to a model against measurements "
                         f"(B a .csv, .npz or .npy file)")
    if args.report == "html" and not args.output:
        raise InputError("--report html: give -o REPORT.html")
    if args.output and args.report != "html":
        raise InputError("-o: only --report html writes a file")
    if args.report == "html" and not args.output.lower().endswith((".html", ".htm")):
        raise InputError(f"-o {args.output}: the report is written as .html")


def run_report(args: argparse.Namespace, robot, m, tol: float) -> int:
    """The report asked for; exit 0 if the model explains the measurements within ``tol``, 1 if not."""
    from ...calibration.iso9283 import iso9283
    from .output import print_json

    if args.report == "html":
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            from ...errors import InputError

            raise InputError("--report html: the plots need matplotlib (pip install 'robkin[plot]')") from None
    rep = iso9283(robot, m.q, m.positions, m.quaternions, rows=m.rows)
    same = rep.stats["position_rms"] <= tol
    if args.report == "iso9283":
        if args.json:
            d = rep.to_dict()
            d.update(model=args.a, measurements=args.b, residuals=rep.stats, tol=tol, same=same)
            print_json(d)
        else:
            print(rep.text())
        return 0 if same else 1
    _write_html(args, robot, m, rep, tol)
    return 0 if same else 1


def _write_html(args: argparse.Namespace, robot, m, rep, tol: float) -> None:
    import numpy as np

    from ...calibration.diagnosis import diagnose
    from ...io.files.atomic import write_text_atomic
    from ...viz.report_html import html_report
    from ...viz.residual_plots import residuals_per_joint, residuals_per_pose
    from .output import wrote

    diag = diagnose(robot, m.q, m.positions, m.quaternions, tol=tol, rows=m.rows)
    head = ["pose", "first row", "n", "AP_p mm", "AP_x mm", "AP_y mm", "AP_z mm", "RP_l mm"]
    if rep.orientations:
        head += ["AP_a deg", "AP_b deg", "AP_c deg", "RP_a deg", "RP_b deg", "RP_c deg"]
    rows = []
    for k, p in enumerate(rep.poses, start=1):
        row = [f"P{k}", str(p.rows[0]), str(p.n), f"{p.ap_p * 1e3:.4f}"] + [f"{v * 1e3:+.4f}" for v in p.ap_xyz]
        row.append("-" if p.rp_l is None else f"{p.rp_l * 1e3:.4f}")
        if rep.orientations and p.ap_abc is not None:
            row += [f"{np.degrees(v):+.4f}" for v in p.ap_abc]
            row += ["-"] * 3 if p.rp_abc is None else [f"{np.degrees(v):.4f}" for v in p.rp_abc]
        rows.append(row)
    sections = [
        ("model against measurements", f"model: {args.a}\nmeasurements: {args.b} ({len(m.q)} poses)\n\n"
                                       + diag.text()),
        ("ISO 9283 pose accuracy and repeatability, per commanded pose", (head, rows)),
        ("definitions", "\n".join(rep.text().splitlines()[len(rep.poses) + 3:])),
        ("residuals per pose", residuals_per_pose(m.rows, rep.residuals)),
        ("residuals per joint", residuals_per_joint(m.q, rep.residuals, rep.joints,
                                                    [j.revolute for j in robot.joints])),
    ]
    write_text_atomic(args.output, html_report(f"robkin check: {robot.name}", sections))
    wrote(args.output)
