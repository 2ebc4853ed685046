"""Every check of a robot tree (``urdf_source.RawUrdf``, whichever format it was read from), in one call."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Mapping

from .findings import SEVERITIES, Finding

__all__ = ["lint_urdf"]


def lint_urdf(raw, package_paths: Mapping[str, Path] | None = None, max_faces: int | None = None,
              mesh_base: str | None = None) -> list[Finding]:
    """Findings of a tolerantly read URDF (``urdf_source.RawUrdf``); its meshes are found from ``mesh_base``
    (default: the file itself; ``--fix`` checks its output with the input's)."""
    from .asset_checks import MAX_FACES, asset_findings
    from .geometry import MeshCache
    from .joint_checks import joint_findings
    from .mass_checks import mass_findings
    from .structure import structure_findings

    meshes = MeshCache(mesh_base or (raw.file if os.path.exists(raw.file) else "."), package_paths)
    found = structure_findings(raw) + joint_findings(raw) + asset_findings(raw, meshes, max_faces or MAX_FACES)
    found += mass_findings(raw, meshes)
    order = {s: k for k, s in enumerate(SEVERITIES)}
    return sorted(found, key=lambda x: (x.line or 0, order[x.severity]))
