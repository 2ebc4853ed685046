"""Type stub of the compiled module ``robkin.compiled.urdf_scan`` (see urdf_scan.pyx)."""

from robkin.io.urdf_joint import UrdfJoint

MAX_ABS: float
NO_LIMIT: float
MAX_DEPTH: int
SUPPORTED_TYPES: tuple[str, ...]
UNSUPPORTED_TYPES: tuple[str, ...]

def scan_urdf(text: str, src: str) -> tuple[str | None, tuple[str, ...], tuple[UrdfJoint, ...]]: ...
