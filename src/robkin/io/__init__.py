"""Reading and writing robots: robot documents (YAML/JSON) and URDF, by file extension."""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import InputError
from ..robot import Robot

__all__ = ["load", "DOCUMENT_EXTENSIONS", "URDF_EXTENSIONS"]

DOCUMENT_EXTENSIONS = (".yaml", ".yml", ".json")
URDF_EXTENSIONS = (".urdf", ".xacro")


def load(path: str | os.PathLike, base_link: str | None = None, tip_link: str | None = None, *,
         allow_xacro: bool = False) -> Robot:
    """Load a Robot from a robot document (.yaml/.yml/.json) or a URDF (.urdf, .xacro).

    ``base_link``/``tip_link`` pick a serial chain out of a URDF tree (ignored for documents, where
    giving them is an error). A .xacro file is a program (it can run code and read files and
    environment variables): it is expanded only with ``allow_xacro=True``, else refused.
    """
    p = Path(path)
    try:
        return _load(p, base_link, tip_link, allow_xacro)
    except InputError as exc:  # errors found past the reader (e.g. by Robot) name the file too
        raise exc.in_source(str(p)) from None


def _load(p: Path, base_link: str | None, tip_link: str | None, allow_xacro: bool) -> Robot:
    ext = p.suffix.lower()
    if ext in DOCUMENT_EXTENSIONS:
        if base_link or tip_link:
            raise InputError(f"{p}: --base-link/--tip-link apply to URDF input only")
        from .document import read_document

        return read_document(p)
    if ext in URDF_EXTENSIONS:
        from .urdf import robot_from_urdf

        return robot_from_urdf(p, base_link=base_link, tip_link=tip_link, allow_xacro=allow_xacro)
    raise InputError(f"{p}: unknown extension '{ext}'; expected one of "
                     f"{', '.join(DOCUMENT_EXTENSIONS + URDF_EXTENSIONS)}")
