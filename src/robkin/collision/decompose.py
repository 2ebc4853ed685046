"""Convex decomposition with CoACD, cached by the mesh's content.

CoACD (Wei et al., SIGGRAPH 2022; PyPI ``coacd``, ``pip install 'robkin[collision]'``) cuts a mesh into
convex parts whose union follows its concavities, where MuJoCo's single hull per mesh fills them.
robkin runs it with ``PARAMETERS``, lighter than CoACD's own defaults (which take minutes per arm on
one core: 150 tree-search iterations of depth 3 on a 50^3 manifold remesh), at most ``MAX_PARTS``
parts per mesh; the measured cost is in ``docs/simulation.md``.

The cache
    A decomposition is stored under ``$XDG_CACHE_HOME/robkin/coacd/`` (default ``~/.cache``), in a
    file named by the SHA-256 of the mesh's arrays, the parameters and CoACD's version: the same mesh
    is decomposed once. The cache is untrusted: a file is read only if it is a regular file (not a
    symbolic link) of at most ``MAX_CACHE_BYTES``, as NumPy arrays without pickles, and used only if
    it holds at most ``MAX_PARTS`` parts of finite vertices inside the mesh's box (grown by 1 % of
    its size) with valid faces; anything else is computed again (and the file replaced). Beside it,
    ``<sha256>.fit`` keeps the numbers of the decomposition's fit report (``decompose_fit``: five
    float64, used only when finite and consistent with the parts). Files are written atomically, the
    folder made private (mode 0700).
"""

from __future__ import annotations

import hashlib
import io
import json
import os
from pathlib import Path

import numpy as np

from .decimate import MissingExtra

__all__ = ["PARAMETERS", "MAX_PARTS", "cache_dir", "decompose", "cached_fit", "remember_fit"]

#: CoACD's parameters used by robkin (see the module doc); concavity threshold 0.05 as CoACD's default.
PARAMETERS = {"threshold": 0.05, "max_convex_hull": 8, "preprocess_resolution": 40, "resolution": 1000,
              "mcts_nodes": 10, "mcts_iterations": 60, "mcts_max_depth": 2, "decimate": True, "max_ch_vertex": 64,
              "seed": 0}
#: Most convex parts per mesh (= PARAMETERS["max_convex_hull"]); a cache file holding more is not used.
MAX_PARTS = 8
#: Largest cache file read (64-vertex hulls: a few kB per part).
MAX_CACHE_BYTES = 8 * 1024 * 1024
#: Triangles handed to CoACD at most: it remeshes to its own resolution anyway, and its cost grows with the input.
MAX_INPUT_FACES = 20_000


def cache_dir() -> Path:
    """``$XDG_CACHE_HOME/robkin/coacd`` (``~/.cache/robkin/coacd`` when the variable is unset or relative)."""
    base = os.environ.get("XDG_CACHE_HOME", "")
    root = Path(base) if base and os.path.isabs(base) else Path.home() / ".cache"
    return root / "robkin" / "coacd"


def _key(V: np.ndarray, F: np.ndarray, version: str) -> str:
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(V, dtype="<f8").tobytes())
    h.update(np.ascontiguousarray(F, dtype="<i8").tobytes())
    h.update(json.dumps({"coacd": version, **PARAMETERS}, sort_keys=True).encode())
    return h.hexdigest()


def _valid(parts: list[tuple[np.ndarray, np.ndarray]], V: np.ndarray) -> bool:
    if not 1 <= len(parts) <= MAX_PARTS:
        return False
    lo, hi = V.min(axis=0), V.max(axis=0)
    pad = 0.01 * float(np.max(hi - lo)) + 1e-12
    for pv, pf in parts:
        if pv.ndim != 2 or pv.shape[1] != 3 or pf.ndim != 2 or pf.shape[1] != 3 or len(pv) < 4 or len(pf) < 4:
            return False
        if not np.isfinite(pv).all() or (pv < lo - pad).any() or (pv > hi + pad).any():
            return False
        if pf.min() < 0 or pf.max() >= len(pv):
            return False
    return True


def _read(path: Path, limit: int) -> bytes | None:
    """The bytes of a regular file (never through a symbolic link) of at most ``limit`` bytes, or None."""
    import stat

    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0))
    except OSError:
        return None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode) or info.st_size > limit:
            return None
        with os.fdopen(fd, "rb") as f:
            fd = -1
            return f.read(limit + 1)
    except OSError:
        return None
    finally:
        if fd >= 0:
            os.close(fd)


def _load(path: Path, V: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]] | None:
    data = _read(path, MAX_CACHE_BYTES)
    if data is None:
        return None
    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as z:
            count = int(z["count"])
            if not 1 <= count <= MAX_PARTS:
                return None
            parts = [(np.asarray(z[f"v{k}"], dtype=np.float64), np.asarray(z[f"f{k}"], dtype=np.int64))
                     for k in range(count)]
    except Exception:  # noqa: BLE001 - a damaged or hostile cache file: decomposed again
        return None
    return parts if _valid(parts, V) else None


def _write(path: Path, data: bytes) -> None:
    from ..io.files.atomic import atomic_file

    try:
        path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
        with atomic_file(path, binary=True) as f:
            f.write(data)
    except Exception:  # noqa: BLE001 - a cache that cannot be written costs time, not the result
        pass


def _store(path: Path, parts: list[tuple[np.ndarray, np.ndarray]]) -> None:
    buf = io.BytesIO()
    arrays = {"count": np.array(len(parts))}
    for k, (pv, pf) in enumerate(parts):
        arrays[f"v{k}"], arrays[f"f{k}"] = pv, pf
    np.savez(buf, **arrays)
    _write(path, buf.getvalue())


def _fit_path(V: np.ndarray, F: np.ndarray) -> Path:
    from importlib.metadata import version

    return cache_dir() / f"{_key(V, F, version('coacd'))}.fit"


#: Numbers of a cached fit report: parts, volume error, hull volume error, reference (1: the mesh, 0: its
#: hull), Hausdorff distance (``decompose_fit.DecompositionReport``), as little-endian float64.
FIT_NUMBERS = 5


def cached_fit(V: np.ndarray, F: np.ndarray, parts: int) -> np.ndarray | None:
    """The fit report's numbers stored beside the cached decomposition of (V, F), if they are sound: five
    finite numbers, the same count of parts, a reference of 0 or 1, a distance >= 0; else None."""
    data = _read(_fit_path(V, F), 8 * FIT_NUMBERS)
    if data is None or len(data) != 8 * FIT_NUMBERS:
        return None
    values = np.frombuffer(data, dtype="<f8")
    if not np.isfinite(values).all() or values[0] != parts or values[3] not in (0.0, 1.0) or values[4] < 0:
        return None
    return values


def remember_fit(V: np.ndarray, F: np.ndarray, values) -> None:
    """Store the fit report's numbers beside the decomposition of (V, F) (see ``cached_fit``)."""
    _write(_fit_path(V, F), np.asarray(values, dtype="<f8").tobytes())


def decompose(V: np.ndarray, F: np.ndarray, *, use_cache: bool = True) -> tuple[list[tuple[np.ndarray, np.ndarray]], bool]:
    """Convex parts [(V_k, F_k)] of the mesh (V, F), and whether they came from the cache."""
    try:
        import coacd
    except ImportError:
        raise MissingExtra("--collision decompose needs CoACD: pip install 'robkin[collision]'") from None
    from importlib.metadata import version

    from .decimate import decimate

    path = cache_dir() / f"{_key(V, F, version('coacd'))}.npz"
    if use_cache and (cached := _load(path, V)) is not None:
        return cached, True
    Vd, Fd = decimate(V, F, MAX_INPUT_FACES) if len(F) > MAX_INPUT_FACES else (V, F)
    coacd.set_log_level("error")
    result = coacd.run_coacd(coacd.Mesh(np.asarray(Vd, dtype=np.float64), np.asarray(Fd, dtype=np.int32)),
                             **PARAMETERS)
    parts = [(np.asarray(pv, dtype=np.float64), np.asarray(pf, dtype=np.int64)) for pv, pf in result][:MAX_PARTS]
    if use_cache and _valid(parts, V):
        _store(path, parts)
    return parts, False
