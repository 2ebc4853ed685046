"""Type stub of the compiled module ``robkin.compiled.scanners.urdf_scan`` (see urdf_scan.pyx)."""

from robkin.io.trees.tree_joint import UrdfJoint

MAX_DEPTH: int

def scan_urdf(text: str, src: str) -> tuple[str | None, tuple[str, ...], tuple[UrdfJoint, ...]]: ...
