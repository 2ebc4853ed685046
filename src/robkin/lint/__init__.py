"""Lint: is a robot file physically right, and will a simulator take it as it is?

``lint_file(path)`` returns a list of ``Finding`` (severity, file, line, element, message, fix); the
URDF checks read the file tolerantly (``urdf_source``) and report every defect with its line:

- ``structure``: dangling, duplicate, cyclic or unreachable links and joints, several roots, names;
- ``joint_checks``: joint types, limits (order, range, effort, velocity), mimic targets, axes;
- ``mass_checks``: moving links without mass, inertias not positive definite or breaking the triangle
  inequality, the centre of mass, mass and inertia against the collision volume (``geometry``), placeholders;
- ``asset_checks``: meshes missing, unreadable, flat, open, too fine, in the wrong unit;
- ``other_formats``: MJCF and SDF (``model_source``: their readers' trees, ``xml_lines``: element lines),
  robot documents and tables (the URDF robkin writes of them), USD (its reader): the same checks, and
  each reader's refusals as findings; ``mjcf_readiness``: MuJoCo's own verdict and silent compiler settings;
- ``report``: text, JSON and SARIF 2.1.0; ``fix_urdf``: the corrected URDF and one line per change.

What MuJoCo, pinocchio and drake refuse or silently change is said per tool in each finding's message.
Only a file that cannot be read at all (missing, too big, not XML) raises ``InputError``.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Mapping

from .checks import lint_urdf
from .findings import ERROR, INFO, SEVERITIES, WARNING, Finding

__all__ = ["lint_file", "lint_urdf", "Finding", "SEVERITIES", "ERROR", "WARNING", "INFO"]


def lint_file(path: str | os.PathLike, *, package_paths: Mapping[str, Path] | None = None,
              allow_xacro: bool = False, max_faces: int | None = None) -> list[Finding]:
    """Every finding of one robot file.

    Parameters
    ----------
    path : str or PathLike
        A URDF (``.urdf``; ``.xacro`` with ``allow_xacro``), MJCF (``.xml``, ``.mjcf``), SDF, robot
        document (``.json``, ``.yaml``) or table gets every check, each with its line (a document's: the
        line naming the element); USD its reader's checks and the joint limits.
    package_paths : mapping of str to Path, optional
        Where ``package://NAME`` mesh files are (NAME -> folder), tried first.
    allow_xacro : bool
        Expand a ``.xacro`` file (it runs code: only for files you trust).
    max_faces : int, optional
        Warn about meshes with more triangles (default ``asset_checks.MAX_FACES``, 200 000).

    Returns
    -------
    list of Finding
        Sorted by line; ``severity`` is ``"error"`` (a simulator refuses the file, or the physics is
        wrong), ``"warning"`` (silently changed, or suspicious) or ``"info"``.

    Raises
    ------
    InputError
        When the file cannot be read at all: missing, too big, not XML, a DTD, not a ``<robot>``.
    """
    p = os.fspath(path)
    if Path(p).suffix.lower() in (".urdf", ".xacro"):
        from .urdf_source import read_urdf

        return lint_urdf(read_urdf(p, allow_xacro=allow_xacro), package_paths, max_faces)
    from .other_formats import lint_other

    return lint_other(p, allow_xacro=allow_xacro, package_paths=package_paths, max_faces=max_faces)
