"""How far two maps of one voxel size agree (a map against brute-force sampling, two seeds, ...).

Both maps are laid on the union of their boxes (they are aligned: corners on multiples of the voxel
in the base frame). A voxel is *reachable* in a map when any of its orientation bins is marked.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .maps import WorkspaceMap

__all__ = ["agreement", "reachable_voxels"]


def reachable_voxels(wmap: WorkspaceMap) -> set[tuple[int, int, int]]:
    """The reachable voxels as global indices (whole voxels from the base origin)."""
    g = wmap.global_index()
    return {(int(i), int(j), int(k)) for i, j, k in np.argwhere(wmap.reachable > 0) + g}


def agreement(a: WorkspaceMap, b: WorkspaceMap) -> dict[str, float]:
    """Agreement of map ``a`` with a reference map ``b`` (same voxel size).

    Returns
    -------
    dict
        - ``recall``: of the voxels ``b`` reaches, the fraction ``a`` reaches too;
        - ``precision``: of the voxels ``a`` reaches, the fraction ``b`` reaches too;
        - ``jaccard``: |A and B| / |A or B| (1 when they mark the same voxels);
        - ``box_agreement``: the fraction of the voxels of the box holding both maps on which they give
          the same verdict, reachable or not (the empty corners of the box count as agreement);
        - ``bin_recall``: of the (voxel, direction) cells ``b`` marks, the fraction ``a`` marks (only
          when both have the same directions, else NaN);
        - ``a_voxels``, ``b_voxels``: how many voxels each reaches.
    """
    if not np.isclose(a.voxel, b.voxel, rtol=1e-12, atol=0):  # one voxel size, to rounding of the files
        raise InputError(f"maps: voxel sizes differ ({a.voxel} m and {b.voxel} m)")
    ga, gb = a.global_index(), b.global_index()
    lo = np.minimum(ga, gb)
    hi = np.maximum(ga + np.array(a.shape), gb + np.array(b.shape))
    same_bins = a.directions.shape == b.directions.shape and np.allclose(a.directions, b.directions)
    k = a.bins.shape[-1] if same_bins else 1

    def laid(m: WorkspaceMap, g: np.ndarray) -> np.ndarray:
        out = np.zeros(tuple(int(s) for s in hi - lo) + (k,), dtype=bool)
        at = tuple(slice(int(s), int(s) + n) for s, n in zip(g - lo, m.shape))
        out[at] = m.bins if same_bins else m.bins.any(axis=-1, keepdims=True)
        return out

    A, B = laid(a, ga), laid(b, gb)
    va, vb = A.any(axis=-1), B.any(axis=-1)
    both, either = int((va & vb).sum()), int((va | vb).sum())
    return {"recall": both / max(int(vb.sum()), 1), "precision": both / max(int(va.sum()), 1),
            "jaccard": both / max(either, 1), "box_agreement": float((va == vb).mean()),
            "bin_recall": float((A & B).sum() / max(int(B.sum()), 1)) if same_bins else float("nan"),
            "a_voxels": float(va.sum()), "b_voxels": float(vb.sum())}
