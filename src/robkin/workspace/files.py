"""A map as a file: a compressed NumPy ``.npz`` archive, written atomically and read back without
pickles, every array's header checked (type, shape, size) before its data is read.

Arrays: ``reachable`` (X, Y, Z) uint16, how many orientation bins each voxel reaches; ``origin`` (3,)
the grid's corner (base frame, m); ``voxel`` () m; ``manipulability`` (X, Y, Z) float64, NaN where
unreached; ``bins`` (X, Y, Z, K) bool; ``directions`` (K, 3); ``best_q`` (X, Y, Z, n) float64;
``samples``, ``seed`` () int64; ``kind``, ``name`` () str; ``joints`` (n,) str; ``format`` () int
(``FORMAT``).
"""

from __future__ import annotations

import zipfile
from typing import Any

import numpy as np

from ..errors import InputError
from .maps import KINDS, WorkspaceMap

__all__ = ["FORMAT", "MAX_MAP_BYTES", "save_map", "load_map"]

#: The file layout's version (the ``format`` array).
FORMAT = 1
#: Largest map read: the sum of its arrays' declared sizes (a 2 cm Panda map with K = 50 is ~0.3 GB
#: before cropping, far less after); anything larger is refused before it is read.
MAX_MAP_BYTES = 2 * 1024 ** 3
_FIELDS = ("reachable", "origin", "voxel", "manipulability", "bins", "directions", "best_q", "samples", "seed",
           "kind", "name", "joints", "format")


def save_map(wmap: WorkspaceMap, path: str) -> None:
    """Write ``wmap`` to ``path`` (.npz, compressed), all or nothing (``robkin.io.files.atomic``)."""
    from ..io.files.atomic import atomic_file

    arrays: dict[str, Any] = {"reachable": wmap.reachable, "origin": np.asarray(wmap.origin, dtype=float),
              "voxel": np.float64(wmap.voxel), "manipulability": wmap.manipulability, "bins": wmap.bins,
              "directions": wmap.directions, "best_q": wmap.best_q, "samples": np.int64(wmap.samples),
              "seed": np.int64(wmap.seed), "kind": np.str_(wmap.kind), "name": np.str_(wmap.name),
              "joints": np.array(wmap.joints, dtype=str), "format": np.int64(FORMAT)}
    with atomic_file(path, binary=True) as fh:
        np.savez_compressed(fh, **arrays)


def load_map(path: str) -> WorkspaceMap:
    """Read the map at ``path`` written by ``save_map``; InputError naming the file and array if it is not one."""
    try:
        archive = zipfile.ZipFile(path)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except (zipfile.BadZipFile, OSError) as exc:
        raise InputError(f"{path}: not a workspace map (.npz archive): {exc}") from None
    with archive:
        names = {m[:-4] for m in archive.namelist() if m.endswith(".npy")}
        missing = [f for f in _FIELDS if f not in names]
        if missing:
            raise InputError(f"{path}: not a robkin workspace map: no array {', '.join(missing)}")
        headers = {f: _header(archive, f, path) for f in _FIELDS}
        total = sum(int(np.prod(s, dtype=np.int64)) * d.itemsize for s, d in headers.values())
        if total > MAX_MAP_BYTES:
            raise InputError(f"{path}: the map's arrays hold {total} bytes; at most {MAX_MAP_BYTES} are read")
        a = {f: _array(archive, f, path, headers[f]) for f in _FIELDS}
    return _checked(a, path)


def _header(archive: zipfile.ZipFile, name: str, path: str) -> tuple[tuple[int, ...], np.dtype]:
    from numpy.lib import format as npformat

    with archive.open(name + ".npy") as stream:
        try:
            version = npformat.read_magic(stream)
            read = npformat.read_array_header_1_0 if version == (1, 0) else npformat.read_array_header_2_0
            shape, _fortran, dtype = read(stream, max_header_size=10000)  # a literal, read without running code
        except (ValueError, OSError, zipfile.BadZipFile) as exc:
            raise InputError(f"{path}: array '{name}' is not a readable .npy array ({exc})") from None
    if dtype.hasobject or dtype.kind not in "biufU":
        raise InputError(f"{path}: array '{name}' holds {dtype}; expected numbers or text")
    return tuple(int(s) for s in shape), dtype


def _array(archive: zipfile.ZipFile, name: str, path: str, header: tuple[tuple[int, ...], np.dtype]) -> np.ndarray:
    with archive.open(name + ".npy") as stream:
        try:
            arr = np.lib.format.read_array(stream, allow_pickle=False)
        except (ValueError, OSError, zipfile.BadZipFile, EOFError) as exc:
            raise InputError(f"{path}: array '{name}' cannot be read ({exc})") from None
    if arr.shape != header[0]:  # pragma: no cover - the same header read twice
        raise InputError(f"{path}: array '{name}' changed shape")
    return arr


def _checked(a: dict[str, np.ndarray], path: str) -> WorkspaceMap:
    def bad(name: str, what: str) -> InputError:
        return InputError(f"{path}: array '{name}': {what}")

    if a["format"].shape != () or int(a["format"]) != FORMAT:
        raise bad("format", f"version {a['format']!r}; this robkin reads version {FORMAT}")
    bins = a["bins"]
    if bins.ndim != 4 or bins.dtype != bool or 0 in bins.shape:
        raise bad("bins", f"expected a non-empty (X, Y, Z, K) bool array, got {bins.dtype} {bins.shape}")
    X, Y, Z, K = bins.shape
    joints = a["joints"]
    if joints.ndim != 1 or joints.dtype.kind != "U" or len(joints) < 1:
        raise bad("joints", "expected the joint names (n,)")
    n = len(joints)
    expect = {"origin": (3,), "voxel": (), "manipulability": (X, Y, Z), "directions": (K, 3),
              "best_q": (X, Y, Z, n), "samples": (), "seed": (), "kind": (), "name": (), "reachable": (X, Y, Z)}
    for name, shape in expect.items():
        if a[name].shape != shape:
            raise bad(name, f"shape {a[name].shape}; expected {shape} (from bins {bins.shape}, {n} joints)")
    for name in ("origin", "voxel", "directions"):
        if a[name].dtype.kind != "f" or not np.isfinite(a[name]).all():
            raise bad(name, "expected finite floats")
    voxel = float(a["voxel"])
    if voxel <= 0:
        raise bad("voxel", f"{voxel}; expected a positive length")
    if not np.allclose(np.linalg.norm(a["directions"], axis=1), 1.0, atol=1e-9):  # written unit to rounding
        raise bad("directions", "expected unit vectors")
    kind = str(a["kind"])
    if kind not in KINDS:
        raise bad("kind", f"'{kind[:40]}' is not one of {', '.join(KINDS)}")
    if not np.array_equal(a["reachable"], bins.sum(axis=-1)):
        raise bad("reachable", "does not count the bins marked in 'bins'")
    for name in ("manipulability", "best_q"):
        if a[name].dtype.kind != "f":
            raise bad(name, "expected floats")
    for name in ("samples", "seed"):
        if a[name].dtype.kind not in "iu":
            raise bad(name, "expected a whole number")
    return WorkspaceMap(origin=a["origin"].astype(float), voxel=voxel, directions=a["directions"].astype(float),
                        bins=bins, manipulability=a["manipulability"].astype(float),
                        best_q=a["best_q"].astype(float), samples=int(a["samples"]), seed=int(a["seed"]),
                        kind=kind, joints=tuple(str(j) for j in joints), name=str(a["name"]))


