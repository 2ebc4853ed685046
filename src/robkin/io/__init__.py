"""Reading and writing robots: robot documents (YAML/JSON), URDF, MJCF, SDF and USD, by file extension."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError
from ..robot import Robot

if TYPE_CHECKING:  # pragma: no cover
    from .trees.model import UrdfModel

__all__ = ["load", "DOCUMENT_EXTENSIONS", "URDF_EXTENSIONS", "MJCF_EXTENSIONS", "SDF_EXTENSIONS",
           "USD_EXTENSIONS", "ROBOT_FILE_EXTENSIONS", "TABLE_EXTENSIONS", "tree_of_file"]

DOCUMENT_EXTENSIONS = (".yaml", ".yml", ".json")
URDF_EXTENSIONS = (".urdf", ".xacro")
MJCF_EXTENSIONS = (".xml", ".mjcf")
SDF_EXTENSIONS = (".sdf",)
#: USD (UsdPhysics articulations; needs usd-core: ``pip install 'robkin[usd]'``): ``io.usd``
USD_EXTENSIONS = (".usda", ".usd", ".usdc")
#: Table files (``robkin convert --format csv`` output, bare rows): ``io.tables.reader``
TABLE_EXTENSIONS = (".csv", ".tsv", ".txt")
#: Robot files holding a tree from which --base-link/--tip-link pick a serial chain.
ROBOT_FILE_EXTENSIONS = URDF_EXTENSIONS + MJCF_EXTENSIONS + SDF_EXTENSIONS + USD_EXTENSIONS


def load(path: str | os.PathLike[str], base_link: str | None = None, tip_link: str | None = None, *,
         allow_xacro: bool = False, representation: str | None = None) -> Robot:
    """Load a Robot from a robot document (.yaml/.yml/.json), a URDF (.urdf, .xacro), an MJCF model
    (.xml, .mjcf), an SDF model (.sdf), a USD articulation (.usda, .usd, .usdc; with usd-core) or a table (.csv, .tsv, .txt: what ``robkin convert --format
    csv`` writes, or bare rows such as ``a d alpha theta``; see ``robkin.io.tables.reader``).

    ``representation`` ('dh', 'mdh', 'hayati', 'poe', 'poe-body', 'rpy-xyz', 'gjd') says which table
    a table file holds where the file does not say (bare rows, a PoE's frame); tables only.

    ``base_link``/``tip_link`` pick a serial chain out of a robot file's tree: links of a URDF or
    SDF, bodies or sites of an MJCF model (giving them for a document is an error). A .xacro file is a
    program (it can run code and read files and environment variables): it is expanded only with
    ``allow_xacro=True``, else refused.
    """
    p = os.fspath(path)  # a str: making a Path costs ~10 us, a share of a small URDF's load
    try:
        return _load(p, base_link, tip_link, allow_xacro, representation)
    except InputError as exc:  # errors found past the reader (e.g. by Robot) name the file too
        raise exc.in_source(p) from None


def _load(p: str, base_link: str | None, tip_link: str | None, allow_xacro: bool,
          representation: str | None = None) -> Robot:
    ext = os.path.splitext(p.rstrip("/" + os.sep))[1].lower()
    if ext in TABLE_EXTENSIONS:
        if base_link or tip_link:
            raise InputError(f"{p}: base_link=/tip_link= apply to robot files (URDF, MJCF, SDF) only")
        from .tables.reader import read_table_file

        return read_table_file(p, representation)
    if representation is not None:
        raise InputError(f"{p}: representation= applies to table files ({', '.join(TABLE_EXTENSIONS)}); "
                         f"this file says what it holds")
    if ext in DOCUMENT_EXTENSIONS:
        if base_link or tip_link:
            raise InputError(f"{p}: base_link=/tip_link= apply to robot files (URDF, MJCF, SDF) only")
        from .documents.reader import read_document

        return read_document(p)
    if ext in URDF_EXTENSIONS:
        from .urdf.chain import robot_from_urdf

        # the robot-file readers read a str starting with '<' as XML text: such a name goes as a Path
        source = Path(p) if p.lstrip().startswith("<") else p
        return robot_from_urdf(source, base_link=base_link, tip_link=tip_link, allow_xacro=allow_xacro)
    if ext in MJCF_EXTENSIONS:
        from .mjcf.reader import robot_from_mjcf

        return robot_from_mjcf(Path(p), base_link=base_link, tip_link=tip_link)
    if ext in SDF_EXTENSIONS:
        from .sdf.reader import robot_from_sdf

        return robot_from_sdf(Path(p), base_link=base_link, tip_link=tip_link)
    if ext in USD_EXTENSIONS:
        from .usd.reader import robot_from_usd

        return robot_from_usd(p, base_link=base_link, tip_link=tip_link)
    raise InputError(f"{p}: unknown extension '{ext}'; expected one of "
                     f"{', '.join(DOCUMENT_EXTENSIONS + ROBOT_FILE_EXTENSIONS + TABLE_EXTENSIONS)}")


def tree_of_file(path: str | os.PathLike[str]) -> tuple[UrdfModel, dict[str, str], str] | None:
    """The tree of a .urdf, MJCF (.xml, .mjcf), SDF (.sdf) or USD (.usda, .usd, .usdc) file, for commands that list its chains.

    Returns (tree, joints on it that make no chain (name -> kind), wording of the joint kinds that do),
    or None for any other file (a document, a .xacro, which goes through the loader and its opt-in).
    """
    ext = Path(path).suffix.lower()
    if ext == ".urdf":
        from .urdf.parser import parse_urdf

        return parse_urdf(path), {}, ""
    if ext in MJCF_EXTENSIONS:
        from .mjcf.reader import CHAIN_JOINTS, model_from_mjcf

        return (*model_from_mjcf(path), CHAIN_JOINTS)
    if ext in SDF_EXTENSIONS:
        from .sdf.reader import CHAIN_JOINTS as SDF_CHAIN_JOINTS, model_from_sdf

        return (*model_from_sdf(path), SDF_CHAIN_JOINTS)
    if ext in USD_EXTENSIONS:
        from .usd.reader import model_from_usd

        return model_from_usd(path), {}, ""
    return None
