"""Type stub of the compiled module ``robkin.compiled.scanners.urdf_scan`` (see urdf_scan.pyx)."""

from typing import Any, Callable, TypeVar

J = TypeVar("J")

MAX_DEPTH: int

def scan_urdf(text: str, src: str, joint_type: Callable[..., J],
              mimic_type: Callable[..., Any]) -> tuple[str | None, tuple[str, ...], tuple[J, ...]]: ...
