"""Many joint vectors or poses from a file, and many results into one: the CLI's batch input/output.

Input (``read_rows``): a CSV file with a header row (``.csv``, or any name holding text), a NumPy
``.npy`` array or an ``.npz`` archive; ``-`` reads standard input (CSV text, or ``.npy`` bytes, told
apart by NumPy's magic string). Arrays are read without pickles and only after their header says
they are numbers of a bounded size, so no file can run code or exhaust memory.

Output (``write_rows``): ``.csv`` (a header, one row per input row), ``.npy`` (one numeric array),
``.npz`` (every column) or ``.json``; written atomically (``robkin.io.files.atomic``).
"""

from __future__ import annotations

import csv
import io
import os
import sys
import zipfile
from itertools import islice
from typing import IO, Any, Callable, Iterable, Iterator, Mapping, Sequence

import numpy as np

from ..errors import InputError
from .files.numbers import number
from .tables.cells import csv_read_cell, csv_text_cell

__all__ = ["MAX_BYTES", "MAX_VALUES", "MAX_ROWS", "MAX_JSON_ROWS", "Rows", "read_rows", "write_rows", "csv_text",
           "write_csv"]

#: Largest batch file read (text or array): 10^6 joint vectors of 6 values as CSV are ~100 MB with
#: every digit, so 256 MB holds any batch that belongs on a command line (larger ones: robkin's Python
#: API); a CSV is parsed row by row into one float array, so memory stays a small multiple of this.
MAX_BYTES = 256 * 1024 * 1024
#: Largest number of values in one array (128 MB of float64): bounds memory whatever the header says.
MAX_VALUES = 16 * 1024 * 1024
#: Most rows of one batch: FK's results and their temporaries peak at ~600 bytes per row (6 joints: q, T,
#: rpy, quaternion, the output file's copies), so 5 * 10^5 rows stay under ~0.4 GB whatever the output
#: (2.7 * 10^6 rows of a 6-joint arm, 33 MB of CSV, fit MAX_VALUES but took 1.9 GB and failed with a
#: MemoryError). Larger batches: split the file, or robkin's Python API.
MAX_ROWS = 500_000
#: Most rows written as JSON (--json, -o .json): a row there is a dict of Python numbers, ~2 kB.
MAX_JSON_ROWS = 100_000
_MAGIC = b"\x93NUMPY"


class Rows:
    """A batch read from a file: ``values`` (N, k) float, ``columns`` (k names, or None without a
    header) and ``shape`` (the array's own shape for .npy/.npz input, e.g. (N, 4, 4)).

    A CSV column holding text (a ``success`` or ``error`` column of robkin's own output) is NaN in
    ``values``; ``take`` raises the message of its first unreadable cell when such a column is used.
    """

    def __init__(self, values: np.ndarray, columns: list[str] | None, shape: tuple[int, ...], source: str,
                 errors: dict[int, str] | None = None):
        self.values, self.columns, self.shape, self.source = values, columns, shape, source
        self.errors = errors or {}

    def take(self, idx: Sequence[int]) -> np.ndarray:
        """The columns ``idx`` (N, len(idx)); InputError if one of them holds something not a number."""
        for i in idx:
            if i in self.errors:
                raise InputError(self.errors[i])
        return self.values[:, list(idx)]

    def __len__(self) -> int:
        return len(self.values)


def _read_bytes(path: str) -> bytes:
    if path == "-":
        data = sys.stdin.buffer.read(MAX_BYTES + 1)
        if len(data) > MAX_BYTES:
            raise InputError(f"-: standard input is more than {MAX_BYTES} bytes; a batch is at most that")
        return data
    from .files.input_files import read_bytes_file

    return read_bytes_file(path, MAX_BYTES, "a batch file")


def read_rows(path: str, key: str = "") -> Rows:
    """The rows of a batch file (see the module). ``key`` names the preferred array of an .npz."""
    data = _read_bytes(path)
    name = "standard input" if path == "-" else path
    if data.startswith(_MAGIC):
        arr = _npy(io.BytesIO(data), name)
        return _as_rows(arr, name)
    if data.startswith(b"PK\x03\x04"):
        return _npz(data, name, key)
    if path.lower().endswith((".npy", ".npz")):
        raise InputError(f"{name}: not a NumPy {os.path.splitext(path)[1]} file (no NumPy header)")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"{name}: not UTF-8 text nor a NumPy array (byte {exc.start})") from None
    return _csv(text, name)


def _npy(stream: Any, name: str) -> np.ndarray:
    """A numeric array from an .npy stream, its header checked before any data is read."""
    from numpy.lib import format as npformat

    try:
        version = npformat.read_magic(stream)
        # the header is a Python literal read by ast.literal_eval (no code runs), at most 10 kB
        read_header = npformat.read_array_header_1_0 if version == (1, 0) else npformat.read_array_header_2_0
        shape, fortran, dtype = read_header(stream, max_header_size=10000)
    except (ValueError, OSError) as exc:
        raise InputError(f"{name}: not a readable .npy array ({str(exc).splitlines()[0][:80]})") from None
    if dtype.hasobject or dtype.kind not in "biuf":
        raise InputError(f"{name}: array of {dtype}; expected numbers (float or integer)")
    count = int(np.prod(shape, dtype=np.int64)) if shape else 1
    if count > MAX_VALUES:
        raise InputError(f"{name}: array of shape {shape} holds {count} values; a batch is at most {MAX_VALUES}")
    raw = stream.read(count * dtype.itemsize)
    if len(raw) != count * dtype.itemsize:
        raise InputError(f"{name}: array data ends early ({len(raw)} of {count * dtype.itemsize} bytes)")
    arr = np.frombuffer(raw, dtype=dtype, count=count)
    arr = arr.reshape(shape[::-1]).T if fortran else arr.reshape(shape)
    return np.array(arr, dtype=float)


def _npz(data: bytes, name: str, key: str) -> Rows:
    try:
        archive = zipfile.ZipFile(io.BytesIO(data))
        members = [m for m in archive.namelist() if m.endswith(".npy")]
    except zipfile.BadZipFile:
        raise InputError(f"{name}: not a readable .npz archive") from None
    if not members:
        raise InputError(f"{name}: the .npz archive holds no array")
    keys = [m[:-4] for m in members]
    pick = key if key in keys else keys[0]
    if len(keys) > 1 and key not in keys:
        raise InputError(f"{name}: the .npz archive holds {', '.join(keys)[:80]}; name the array '{key}' "
                         f"(or save only one)")
    info = archive.getinfo(pick + ".npy")
    if info.file_size > MAX_BYTES:
        raise InputError(f"{name}: array '{pick}' is {info.file_size} bytes; a batch is at most {MAX_BYTES}")
    with archive.open(info) as stream:
        return _as_rows(_npy(stream, f"{name}['{pick}']"), name)


def _as_rows(arr: np.ndarray, name: str) -> Rows:
    if arr.ndim == 1:
        arr = arr[None]
    if arr.ndim < 2 or arr.shape[0] == 0:
        raise InputError(f"{name}: array of shape {arr.shape}; expected one row per item, (N, ...)")
    if arr.shape[0] > MAX_ROWS:
        raise InputError(f"{name}: {arr.shape[0]} rows; a batch is at most {MAX_ROWS} rows (split the file)")
    return Rows(arr.reshape(arr.shape[0], -1), None, arr.shape, name)


def _data_lines(text: str) -> Iterator[tuple[int, str]]:
    """(line number, line) of the lines holding data (not blank, not a # comment), one at a time: a
    batch of 10^6 lines is never held as a list of strings."""
    start, k, size = 0, 0, len(text)
    while start < size:  # str.find, not io.StringIO (a copy 4 bytes a character) nor splitlines (a list)
        end = text.find("\n", start)
        end = size if end < 0 else end
        line, start, k = text[start:end].rstrip("\r"), end + 1, k + 1
        if line.strip() and not line.lstrip().startswith("#"):
            yield k, line


def _csv(text: str, name: str) -> Rows:
    first_line = next(_data_lines(text), None)
    if first_line is None:
        raise InputError(f"{name}: no rows")
    tab = "\t" in first_line[1] and "," not in first_line[1]
    delimiter = "\t" if tab else ","
    first = [c.strip() for c in next(csv.reader([first_line[1]], delimiter=delimiter))]
    header: list[str] | None = None
    if first and not _is_number(first[0]):
        header = [csv_read_cell(c) for c in first]  # names as written (csv_text_cell undone)
    # the data lines, counted only up to the cap: a huge file is refused without reading it all
    n_rows = sum(1 for _ in islice(_data_lines(text), MAX_ROWS + 2)) - (header is not None)
    if not n_rows:
        raise InputError(f"{name}: no rows after the header")
    width = len(header) if header else len(first)
    if n_rows > MAX_ROWS:  # counted up to the cap only
        raise InputError(f"{name}: more than {MAX_ROWS} rows; a batch is at most {MAX_ROWS} rows (split the file)")
    if n_rows * width > MAX_VALUES:
        raise InputError(f"{name}: {n_rows} rows of {width} values; a batch is at most {MAX_VALUES} values")
    out = np.empty((n_rows, width))
    errors: dict[int, str] = {}
    lines = _data_lines(text)
    if header is not None:
        next(lines)
    numbered = [0]

    def unnumbered() -> Iterator[str]:
        for k, line in lines:
            numbered[0] = k
            yield line

    reader = csv.reader(unnumbered(), delimiter=delimiter)
    for i, raw in enumerate(reader):
        k = numbered[0]
        row = [c.strip() for c in raw]
        if len(row) != width:
            raise InputError(f"{name}: line {k}: expected {width} values, got {len(row)}")
        for j, cell in enumerate(row):
            try:
                out[i, j] = _cell(cell, name, k, header[j] if header else str(j + 1))
            except InputError as exc:
                if header is None:  # without a header every column is data
                    raise
                out[i, j] = np.nan
                errors.setdefault(j, str(exc))
    read = i + 1 if n_rows else 0
    if read != n_rows:  # a quoted field spanning lines joined some of them
        out = out[:read]
    return Rows(out, header, out.shape, name, errors)


def _is_number(cell: str) -> bool:
    try:
        number(cell, "")
    except InputError:
        return False
    return True


def _cell(cell: str, name: str, line: int, column: str) -> float:
    """A CSV cell: a number (fast path), an expression such as pi/2, or empty/'nan' (not a number:
    kept as NaN, for columns the command does not use). Infinity is refused by the user of the column."""
    try:
        return float(cell)
    except ValueError:
        pass
    if cell == "" or cell.lower() in ("nan", "null", "none"):
        return float("nan")
    return number(cell, f"{name}: line {line}, column {column[:40]}")


def csv_text(columns: Sequence[str], table: Iterable[Sequence[Any]]) -> str:
    """CSV text with a header: floats so that they read back bit for bit, booleans true/false."""
    buf = io.StringIO()
    write_csv(buf, columns, table)
    return buf.getvalue()


def write_csv(stream: IO[str], columns: Sequence[str], table: Iterable[Sequence[Any]]) -> None:
    """``csv_text`` written to ``stream`` row by row (``table`` may be a generator: no list of rows)."""
    from .files.float_text import float_text

    def cell(v: Any) -> str:
        if isinstance(v, (bool, np.bool_)):
            return "true" if v else "false"
        if isinstance(v, (float, np.floating)):
            return "nan" if not np.isfinite(v) else float_text(float(v))
        text = str(v)
        return text if _is_number(text) else csv_text_cell(text)  # no spreadsheet formula from a name

    w = csv.writer(stream, lineterminator="\n")
    w.writerow([csv_text_cell(str(c)) for c in columns])
    for row in table:
        w.writerow([cell(v) for v in row])


def write_rows(path: str, columns: Sequence[str], table: Iterable[Sequence[Any]] | Callable[[], Iterable[Sequence[Any]]],
               arrays: Mapping[str, np.ndarray | Callable[[], np.ndarray]], main_array: str,
               document: Any) -> None:
    """Write a batch's results to ``path`` by its extension (atomically).

    ``.csv``: ``columns`` and ``table`` (rows, or a function giving them: called only here, so the
    rows are made, one at a time if it is a generator, only for CSV); ``.npy``: ``arrays[main_array]``;
    ``.npz``: every array of ``arrays``; ``.json``: ``document`` (or a function giving it; robkin's
    JSON style). An array may be given as a function giving it, called only for the file that holds it.
    """
    from .files.atomic import atomic_file, write_text_atomic

    ext = os.path.splitext(path)[1].lower()
    if ext == ".csv":
        with atomic_file(path) as f:
            write_csv(f, columns, table() if callable(table) else table)
    elif ext == ".json":
        from .files.jsontext import dumps

        write_text_atomic(path, dumps(document() if callable(document) else document) + "\n")
    elif ext in (".npy", ".npz"):
        with atomic_file(path, binary=True) as f:
            if ext == ".npy":
                np.save(f, _array(arrays[main_array]), allow_pickle=False)
            else:
                np.savez(f, **{k: _array(v) for k, v in arrays.items()})
    else:
        raise InputError(f"{path}: unknown output extension '{ext}'; -o writes .csv, .npy, .npz or .json")


def _array(value: Any) -> np.ndarray:
    """An output array, or the array a function gives (made only when written)."""
    return np.asarray(value() if callable(value) else value)
