"""Outputs of ``robkin calibrate`` for a robot controller: joint offsets, the table in the source's
convention, and filtered targets.

- ``offsets_csv``: one line per joint, ``joint, offset, unit, identified``. The offset is the calibrated
  joint zero minus the nominal one, in the joint's own coordinate (rad, m; the joint's sign): the real
  joint at encoder value q sits where the nominal model puts q + offset. A controller that keeps joint
  offsets (mastering / zero calibration) adds it to its own; ``identified`` false means the measurements
  could not tell it (a free base absorbs the first joint's zero, a free marker the last one's) and 0 is
  written.
- ``table_text``: the calibrated robot with the nominal flange kept (``frames.written_robot(...,
  keep_frames=True)``: the table a controller's kinematics hold ends at the flange, in the robot's base
  frame) as a table in the source's convention (a DH, modified DH or Hayati source: the same; else the
  one asked for), CSV, Markdown, LaTeX or a robot document by the extension.
- ``filter_targets``: for target flange poses in the robot base frame, the joint values that bring the
  *calibrated* robot there, found by IK started from the nominal controller's own solution (the same
  branch), and the *filtered* pose, the nominal model's FK of them: a controller running the nominal
  kinematics, sent the filtered pose, commands those joint values and the real robot reaches the target.
  With a ``payload`` column and a calibrated stiffness, the joint values also undo the deflection.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from ...errors import InputError, quote
from ...robot import Robot

__all__ = ["offsets_csv", "table_text", "filter_targets", "filtered_csv", "read_targets", "TARGET_COLUMNS"]

TARGET_COLUMNS = ("x", "y", "z", "qw", "qx", "qy", "qz")
#: Most targets read: far beyond a robot program's points, bounds the IK work.
MAX_TARGETS = 100_000


def offsets_csv(result, nominal: Robot) -> str:
    """The joint offsets file (see the module doc)."""
    from ...io.tables.cells import csv_text_cell

    by_name = {p.name: p for p in result.parameters}
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["joint", "offset", "unit", "identified"])
    for j in nominal.joints:
        p = by_name.get(f"joint {j.name} zero offset")
        sign = -1.0 if (j.flip and result.model != "poe") else 1.0
        value = 0.0 if p is None or not p.identified else sign * (p.estimate - p.nominal)
        w.writerow([csv_text_cell(j.name), repr(float(value) + 0.0), "rad" if j.revolute else "m",
                    "true" if p is not None and p.identified else "false"])
    return buf.getvalue()


def table_text(robot: Robot, nominal: Robot, path: str | Path, convention: str | None) -> str:
    """The calibrated ``robot`` (flange kept) as a table file named ``path`` (see the module doc)."""
    from ...io.tables.files import TABLE_EXTENSIONS, render_table
    from ...representations.registry import names

    ext = Path(path).suffix.lower()
    rep = convention or {"dh": "dh", "mdh": "mdh", "hayati": "hayati"}.get(nominal.frames_from or "")
    if rep is None:
        raise InputError(f"--table {path}: the model is not a DH, modified DH or Hayati table, so it has no "
                         f"table convention of its own: give --to (one of {', '.join(sorted(names()))})")
    formats = {e: f for f, e in TABLE_EXTENSIONS.items()}
    if ext in formats:
        return render_table(robot, rep, formats[ext], digits="exact")
    if ext in (".yaml", ".yml", ".json"):
        from ...io.documents.reader import document_from_robot, dump
        from ...representations.registry import by_name

        return dump(document_from_robot(robot, (by_name(rep).section,)), "json" if ext == ".json" else "yaml")
    raise InputError(f"--table {path}: a table is written as {', '.join(formats)}, .yaml, .yml or .json")


def read_targets(path: str, robot: Robot) -> tuple[np.ndarray, np.ndarray | None]:
    """Target poses (N, 4, 4) in the robot base frame and payloads (N,) or None from a CSV with columns
    x, y, z, qw, qx, qy, qz [, payload]; the other columns ``robkin fk -o`` writes (row, the joints, roll,
    pitch, yaw, success, error) are ignored, so its output is a targets file; any other column is an
    error (a typo must not drop the payload). InputError naming the file, line and column otherwise."""
    from ...calibration.inputs import _matrix_from_quaternion
    from ...calibration.measurements import MAX_BYTES
    from ...io.files.input_files import read_text_file
    from ...io.tables.cells import csv_read_cell

    text = read_text_file(path, MAX_BYTES, "a targets file")
    if "\0" in text:
        raise InputError(f"{path}: holds a NUL character; a targets file is CSV text")
    ignored = {"row", "roll", "pitch", "yaw", "success", "error"} | {j.name for j in robot.joints}
    wanted = TARGET_COLUMNS + ("payload",)
    header: list[str] | None = None
    rows: list[list[float]] = []
    try:
        for line_no, record in enumerate(csv.reader(io.StringIO(text)), start=1):
            if not record or not "".join(record).strip() or record[0].lstrip().startswith("#"):
                continue
            if header is None:
                header = [csv_read_cell(h.strip()) for h in record]
                unknown = [h for h in header if h not in wanted and h not in ignored]
                missing = [c for c in TARGET_COLUMNS if c not in header]
                if unknown or missing or len(set(header)) != len(header):
                    what = f"column {quote(unknown[0])} is not known" if unknown else \
                        f"no column {quote(missing[0])}" if missing else "a column appears twice"
                    raise InputError(f"{path}: {what}; expected {', '.join(TARGET_COLUMNS)} [, payload]")
                continue
            if len(record) != len(header):
                raise InputError(f"{path}: line {line_no}: {len(record)} values for {len(header)} columns")
            values = []
            for h, cell in zip(header, record):
                if h not in wanted:
                    continue
                try:
                    v = float(cell)
                except ValueError:
                    raise InputError(f"{path}: line {line_no}, column {quote(h)}: {quote(cell.strip())} is not a "
                                     f"number") from None
                if not abs(v) <= 1e9:   # also NaN: no target lies a million kilometres away
                    raise InputError(f"{path}: line {line_no}, column {quote(h)}: not a finite number")
                values.append(v)
            rows.append(values)
            if len(rows) > MAX_TARGETS:
                raise InputError(f"{path}: more than {MAX_TARGETS} targets")
    except csv.Error as exc:
        raise InputError(f"{path}: not CSV ({exc})") from None
    if header is None or not rows:
        raise InputError(f"{path}: no targets; expected a header {', '.join(TARGET_COLUMNS)} and one pose per line")
    A = np.array(rows)
    col = {h: A[:, k] for k, h in enumerate(h for h in header if h in wanted)}
    qt = np.stack([col[c] for c in TARGET_COLUMNS[3:]], axis=1)
    norms = np.linalg.norm(qt, axis=1)
    bad = np.flatnonzero(~(np.abs(norms - 1.0) <= 1e-3))   # 3-4 typed digits, as measurement files
    if bad.size:
        raise InputError(f"{path}: target {bad[0] + 1}: quaternion (qw, qx, qy, qz) has norm {norms[bad[0]]:.6g}, "
                         f"not 1")
    payloads = col.get("payload")
    if payloads is not None:
        from ...calibration.compliance import check_payloads

        payloads = check_payloads(payloads, len(A))
    T = np.tile(np.eye(4), (len(A), 1, 1))
    T[:, :3, :3] = _matrix_from_quaternion(qt / norms[:, None])
    T[:, :3, 3] = np.stack([col[c] for c in TARGET_COLUMNS[:3]], axis=1)
    return T, payloads


def filter_targets(calibrated: Robot, nominal: Robot, targets: np.ndarray, payloads: np.ndarray | None = None
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Joint values (N, n), filtered poses (N, 4, 4), success (N,) and reached position error (N,) (m).

    ``calibrated``: the calibrated robot with the nominal flange and base frame (``keep_frames``).
    """
    nom = nominal.ik(targets)
    start = np.where(np.isfinite(nom.q), nom.q, nominal.home())   # where the nominal IK failed: the home
    cal = calibrated.ik(targets, q0=start)
    ok = np.asarray(cal.success, dtype=bool) & np.all(np.isfinite(cal.q), axis=-1)
    q_link = np.where(ok[:, None], cal.q, start)   # a target out of reach: reported, not NaN
    q = q_link
    if payloads is not None and any(j.stiffness for j in calibrated.joints):
        from ...calibration.compliance import holding_torques

        c = np.array([0.0 if j.stiffness is None else 1.0 / j.stiffness for j in calibrated.joints])
        q = q_link + c * holding_torques(calibrated, q_link, payloads)   # command past the deflection
    reached = calibrated.fk_compliant(q, 0.0 if payloads is None else payloads)
    error = np.linalg.norm(reached[:, :3, 3] - targets[:, :3, 3], axis=1)
    return q, nominal.fk(q), ok, error


def filtered_csv(robot: Robot, q: np.ndarray, poses: np.ndarray, success: np.ndarray, error: np.ndarray) -> str:
    """The filter's output: joint values, the filtered pose (x, y, z, qw, qx, qy, qz), reached, error (m)."""
    from ... import se3
    from ...io.tables.cells import csv_text_cell

    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([csv_text_cell(j.name) for j in robot.joints] + list(TARGET_COLUMNS) + ["reached", "error"])
    for qi, T, ok, e in zip(q, poses, success, error):
        quat = se3.quaternion_from_matrix(T[:3, :3])
        w.writerow([repr(float(v)) for v in qi] + [repr(float(v)) for v in T[:3, 3]] +
                   [repr(float(v)) for v in quat] + ["true" if ok else "false", repr(float(e))])
    return buf.getvalue()

