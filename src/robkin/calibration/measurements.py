"""Measurement files: joint values and the measured point (and orientation) per pose.

CSV (``.csv``): a header line, then one pose per line. Columns, in any order: one per joint named as
the model's joints (q in radians or metres), ``x``, ``y``, ``z`` (the measured point in the measuring
device's frame, metres), optionally ``qw``, ``qx``, ``qy``, ``qz`` (a unit quaternion of the measured
orientation, all four or none) and ``payload`` (the mass the robot carried at that pose, kg, >= 0: for
compliance, ``robkin.calibration.compliance``). Other columns are refused (a typo must not silently drop a joint).
Blank lines and lines starting with ``#`` are skipped.

NumPy (``.npz``): one array per column name, as in the CSV (each of length N), or ``q`` (N, n),
``positions`` (N, 3) and optionally ``quaternions`` (N, 4) (w, x, y, z) and ``payloads`` (N,).
``.npy``: a structured array
with the CSV's column names as fields, or a plain (N, n + 3) or (N, n + 7) array whose columns are in
the CSV order (joints, x, y, z[, qw, qx, qy, qz]). NumPy files are read without pickles, so loading them
runs no code.
"""

from __future__ import annotations

import csv
import io
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

import numpy as np

from ..compiled.scanners.vocabulary import MAX_ABS  # the documents' bound on any number
from ..errors import InputError, quote
from ..robot import Robot

__all__ = ["Measurements", "read_measurements", "write_measurements_csv", "MAX_BYTES", "MAX_POSES"]

#: Largest measurement file read (bytes): 10^5 poses of a 7-joint arm in CSV are ~15 MB.
MAX_BYTES = 64 * 1024 * 1024
#: Most poses accepted: far beyond any calibration campaign (30-1000 poses), and bounds the fit's memory.
MAX_POSES = 200_000
POSITION_COLUMNS = ("x", "y", "z")
QUATERNION_COLUMNS = ("qw", "qx", "qy", "qz")
PAYLOAD_COLUMN = "payload"
#: A quaternion whose norm is within this of 1 is normalised (4-6 typed digits); beyond, refused.
QUATERNION_TOL = 1e-3


@dataclass
class Measurements:
    """Poses read from a file: q (N, n), positions (N, 3), quaternions (N, 4) (w, x, y, z) or None, and the
    line number of each pose in the file (for messages and the outlier list); payloads (N,) (kg) or None."""

    q: np.ndarray
    positions: np.ndarray
    quaternions: np.ndarray | None
    rows: list[int]
    payloads: np.ndarray | None = None


def read_measurements(path: str | os.PathLike[str], robot: Robot) -> Measurements:
    """Read a measurement file (see the module doc) for ``robot``'s joints; InputError naming the file,
    line and column otherwise.

    ``path``: the CSV file; ``robot``: whose joint names the columns must carry.
    """
    p = os.fspath(path)
    ext = Path(p).suffix.lower()
    names = [j.name for j in robot.joints]
    if ext == ".csv":
        from ..io.files.input_files import read_text_file

        m = _from_csv(read_text_file(p, MAX_BYTES, "a measurement file"), names, p)
    elif ext in (".npz", ".npy"):
        from ..io.files.input_files import read_bytes_file

        m = _from_numpy(read_bytes_file(p, MAX_BYTES, "a measurement file"), ext, names, p)
    else:
        raise InputError(f"{p}: a measurement file is .csv, .npz or .npy")
    if len(m.q) < 3:
        raise InputError(f"{p}: {len(m.q)} poses; calibration needs many more (30-100, see the guide)")
    if m.quaternions is not None:
        norms = np.linalg.norm(m.quaternions, axis=1)
        bad = np.flatnonzero(~(np.abs(norms - 1.0) <= QUATERNION_TOL))
        if bad.size:
            raise InputError(f"{p}: line {m.rows[bad[0]]}: quaternion (qw, qx, qy, qz) has norm {norms[bad[0]]:.6g}; "
                             f"a unit quaternion is needed")
        m.quaternions = m.quaternions / norms[:, None]
    if m.payloads is not None:
        from .compliance import MAX_PAYLOAD

        bad = np.flatnonzero(~((m.payloads >= 0) & (m.payloads <= MAX_PAYLOAD)))
        if bad.size:
            raise InputError(f"{p}: line {m.rows[bad[0]]}, column 'payload': {m.payloads[bad[0]]:g} is not a mass "
                             f"in [0, {MAX_PAYLOAD:g}] kg")
    return m


def _columns_expected(names: list[str]) -> str:
    return ", ".join(names + list(POSITION_COLUMNS)) + " [, qw, qx, qy, qz] [, payload]"


def _check_header(header: list[str], names: list[str], src: str) -> list[str]:
    from ..io.tables.cells import csv_read_cell

    header = [csv_read_cell(h.strip()) for h in header]  # names as written (csv_text_cell undone)
    known = set(names) | set(POSITION_COLUMNS) | set(QUATERNION_COLUMNS) | {PAYLOAD_COLUMN}
    for h in header:
        if h not in known:
            raise InputError(f"{src}: column {quote(h)} is neither a joint of the model nor x, y, z, qw, qx, qy, qz, "
                             f"payload; "
                             f"expected {_columns_expected(names)}")
    seen: set[str] = set()
    for h in header:
        if h in seen:
            raise InputError(f"{src}: column {quote(h)} appears twice")
        seen.add(h)
    missing = [c for c in names + list(POSITION_COLUMNS) if c not in seen]
    if missing:
        raise InputError(f"{src}: no column {', '.join(quote(c) for c in missing[:4])}; expected "
                         f"{_columns_expected(names)}")
    quat = [c for c in QUATERNION_COLUMNS if c in seen]
    if quat and len(quat) != 4:
        raise InputError(f"{src}: orientation columns {', '.join(quat)} without "
                         f"{', '.join(c for c in QUATERNION_COLUMNS if c not in seen)}: give all of qw, qx, qy, qz or none")
    return header


def _from_csv(text: str, names: list[str], src: str) -> Measurements:
    if "\0" in text:
        raise InputError(f"{src}: holds a NUL character; a measurement file is CSV text")
    reader = csv.reader(io.StringIO(text))
    header: list[str] | None = None
    values: list[list[float]] = []
    rows: list[int] = []
    for line_no, record in enumerate(_records(reader, src), start=1):
        if not record or not "".join(record).strip() or record[0].lstrip().startswith("#"):
            continue
        if header is None:
            header = _check_header(record, names, src)
            continue
        if len(record) != len(header):
            raise InputError(f"{src}: line {line_no}: {len(record)} values for {len(header)} columns")
        row = []
        for col, cell in zip(header, record):  # noqa: B905 - lengths checked above
            try:
                v = float(cell)
            except ValueError:
                raise InputError(f"{src}: line {line_no}, column {quote(col)}: {quote(cell.strip())} is not a "
                                 f"number") from None
            if not abs(v) <= MAX_ABS:  # also NaN: a pose of 1e308 is no measurement (the fit would blame the spread)
                raise InputError(f"{src}: line {line_no}, column {quote(col)}: {quote(cell.strip())} is not a finite "
                                 f"number of magnitude at most {MAX_ABS:g}")
            row.append(v)
        values.append(row)
        rows.append(line_no)
        if len(values) > MAX_POSES:
            raise InputError(f"{src}: more than {MAX_POSES} poses")
    if header is None:
        raise InputError(f"{src}: empty; expected a header line {_columns_expected(names)} and one line per pose")
    A = np.array(values, dtype=float).reshape(len(values), len(header))
    return _assemble({h: A[:, k] for k, h in enumerate(header)}, names, rows)


def _records(reader: Iterator[list[str]], src: str) -> Iterator[list[str]]:
    """The CSV records, a malformed line (a field beyond csv's size limit, a stray quote) as InputError."""
    while True:
        try:
            yield next(reader)
        except StopIteration:
            return
        except csv.Error as exc:
            raise InputError(f"{src}: line {getattr(reader, 'line_num', '?')}: not CSV ({exc})") from None


def _assemble(col: dict[str, np.ndarray], names: list[str], rows: list[int]) -> Measurements:
    q = np.stack([col[n] for n in names], axis=1)
    pos = np.stack([col[c] for c in POSITION_COLUMNS], axis=1)
    quat = np.stack([col[c] for c in QUATERNION_COLUMNS], axis=1) if "qw" in col else None
    return Measurements(q, pos, quat, rows, col.get(PAYLOAD_COLUMN))


def _npy_array(data: bytes, src: str, member: str = "") -> np.ndarray:
    """One .npy payload, its header checked before any allocation: plain dtype (no objects, so no
    pickles), and a shape whose data the bytes actually hold (a header may claim any size)."""
    from numpy.lib import format as npy

    where = f"{src}{': ' + member if member else ''}"
    f = io.BytesIO(data)
    try:
        version = npy.read_magic(f)
        shape, fortran, dtype = (npy.read_array_header_1_0(f) if version == (1, 0) else npy.read_array_header_2_0(f))
    except Exception as exc:  # numpy raises ValueError, OSError, SyntaxError... for a bad header
        raise InputError(f"{where}: not a NumPy .npy array ({type(exc).__name__})") from None
    if dtype.hasobject:
        raise InputError(f"{where}: holds Python objects; only numbers are read (objects would need pickles)")
    count = int(np.prod(shape, dtype=np.int64)) if shape else 1
    if count * dtype.itemsize > len(data) - f.tell():
        raise InputError(f"{where}: the header promises {count * dtype.itemsize} bytes of data, the file holds "
                         f"{len(data) - f.tell()}")
    try:
        return np.asarray(npy.read_array(io.BytesIO(data), allow_pickle=False))
    except Exception as exc:
        raise InputError(f"{where}: not a readable NumPy array ({type(exc).__name__})") from None


def _npz_arrays(data: bytes, src: str) -> dict[str, np.ndarray]:
    """The arrays of an .npz (a zip of .npy files), each member's unpacked size checked first."""
    import zipfile

    try:
        z = zipfile.ZipFile(io.BytesIO(data))
        infos = z.infolist()
        if sum(i.file_size for i in infos) > MAX_BYTES or len(infos) > 64:
            raise InputError(f"{src}: unpacks to more than {MAX_BYTES} bytes or 64 arrays")
        out = {}
        for info in infos:
            name = info.filename[:-4] if info.filename.endswith(".npy") else info.filename
            out[name] = _npy_array(z.read(info), src, name)
        return out
    except InputError:
        raise
    except Exception as exc:  # a damaged or foreign zip
        raise InputError(f"{src}: not a readable .npz file ({type(exc).__name__})") from None


def _from_numpy(data: bytes, ext: str, names: list[str], src: str) -> Measurements:
    if ext == ".npz":
        arrays = _npz_arrays(data, src)
        if "q" in arrays or "positions" in arrays:
            for key in ("q", "positions"):
                if key not in arrays:
                    raise InputError(f"{src}: array 'q' needs 'positions' (N, 3) with it, and 'positions' needs 'q'")
            q = _numeric(arrays["q"], src, "q", (None, len(names)))
            pos = _numeric(arrays["positions"], src, "positions", (len(q), 3))
            quat = _numeric(arrays["quaternions"], src, "quaternions", (len(q), 4)) if "quaternions" in arrays else None
            pay = _numeric(arrays["payloads"], src, "payloads", (len(q),)) if "payloads" in arrays else None
            return Measurements(q, pos, quat, list(range(1, len(q) + 1)), pay)
        _check_header(list(arrays), names, src)
        count: int | None = None
        columns: dict[str, np.ndarray] = {}
        for k, a in arrays.items():
            columns[k] = _numeric(a, src, k, (count,))
            count = len(columns[k])
        return _assemble(columns, names, list(range(1, (count or 0) + 1)))
    a = _npy_array(data, src)
    if a.dtype.names:
        _check_header(list(a.dtype.names), names, src)
        fields = {k: _numeric(np.asarray(a[k]), src, k, (None,)) for k in a.dtype.names}
        return _assemble(fields, names, list(range(1, len(a) + 1)))
    n = len(names)
    if a.ndim != 2 or a.shape[1] not in (n + 3, n + 7):
        raise InputError(f"{src}: a plain array must be (N, {n + 3}) or (N, {n + 7}) (columns "
                         f"{_columns_expected(names)}), got shape {a.shape}")
    A = _numeric(a, src, "array", (None, a.shape[1]))
    header = names + list(POSITION_COLUMNS) + (list(QUATERNION_COLUMNS) if a.shape[1] == n + 7 else [])
    return _assemble({h: A[:, k] for k, h in enumerate(header)}, names, list(range(1, len(A) + 1)))


def _numeric(a: np.ndarray, src: str, name: str, shape: tuple[int | None, ...]) -> np.ndarray:
    if a.dtype.kind not in "fiu":
        raise InputError(f"{src}: array {quote(name)} holds {a.dtype} values, not numbers")
    if a.ndim != len(shape) or any(s is not None and s != t for s, t in zip(shape, a.shape)):
        want = "(" + ", ".join("N" if s is None else str(s) for s in shape) + ")"
        raise InputError(f"{src}: array {quote(name)} has shape {a.shape}, expected {want}")
    if len(a) > MAX_POSES:
        raise InputError(f"{src}: more than {MAX_POSES} poses")
    a = a.astype(float)
    bad = np.argwhere(~(np.abs(a) <= MAX_ABS))  # also NaN
    if bad.size:
        at = f", column {bad[0][1] + 1}" if a.ndim == 2 else ""
        raise InputError(f"{src}: array {quote(name)}, pose {bad[0][0] + 1}{at}: not a finite number of magnitude "
                         f"at most {MAX_ABS:g}")
    return a


def write_measurements_csv(path: str | os.PathLike[str], robot: Robot, q: np.ndarray, positions: np.ndarray,
                           quaternions: np.ndarray | None = None, payloads: np.ndarray | None = None) -> None:
    """Write poses in the CSV contract (atomically), numbers in full precision; ``payloads`` (N,) kg
    as the ``payload`` column."""
    from ..io.files.atomic import write_text_atomic
    from ..io.tables.cells import csv_text_cell

    header = [j.name for j in robot.joints] + list(POSITION_COLUMNS) + \
        (list(QUATERNION_COLUMNS) if quaternions is not None else []) + \
        ([PAYLOAD_COLUMN] if payloads is not None else [])
    parts = [q, positions] + ([quaternions] if quaternions is not None else []) + \
        ([np.asarray(payloads, dtype=float).reshape(-1, 1)] if payloads is not None else [])
    A = np.concatenate(parts, axis=1)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([csv_text_cell(h) for h in header])  # a joint name starting a formula gets its quote
    for row in A:
        w.writerow([repr(float(v)) for v in row])
    write_text_atomic(path, buf.getvalue())
