"""The face budget: a mesh with more triangles than ``max_faces`` is decimated to at most that many.

Quadric edge collapse (Garland-Heckbert) by ``fast-simplification`` (PyPI, the wrapper of Sven
Forstmann's Fast-Quadric-Mesh-Simplification that PyVista uses; ``pip install 'robkin[collision]'``):
about a second for a million triangles, and the shape stays within a small fraction of its size. The
collapse may leave a few triangles more than asked for; a second pass takes them off.
"""

from __future__ import annotations

import numpy as np

__all__ = ["DEFAULT_MAX_FACES", "MissingExtra", "decimate"]

#: ``--max-faces`` default: MuJoCo's limit on an STL file (its reader refuses more).
DEFAULT_MAX_FACES = 200_000


class MissingExtra(ImportError):
    """An optional dependency is not installed; the message names the extra that brings it."""


def decimate(V: np.ndarray, F: np.ndarray, max_faces: int) -> tuple[np.ndarray, np.ndarray]:
    """(V, F) with at most ``max_faces`` triangles (unchanged when it has no more)."""
    if len(F) <= max_faces:
        return V, F
    try:
        import fast_simplification
    except ImportError:
        raise MissingExtra("decimating a mesh to --max-faces needs fast-simplification: "
                           "pip install 'robkin[collision]'") from None
    points, faces = np.ascontiguousarray(V, dtype=np.float32), np.ascontiguousarray(F, dtype=np.int32)
    for _ in range(3):
        reduction = 1.0 - max_faces / len(faces)
        points, faces = fast_simplification.simplify(points, faces, target_reduction=min(max(reduction, 0.0), 0.999))
        if len(faces) <= max_faces:
            break
    if len(faces) > max_faces:  # pragma: no cover - the collapse stalled (a mesh of disjoint triangles)
        faces = faces[:max_faces]
    return np.asarray(points, dtype=np.float64), np.asarray(faces, dtype=np.int64)
