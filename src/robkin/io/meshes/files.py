"""The mesh files a robot file names: found on disk, checked, and copied beside an output.

A URDF, MJCF or SDF names its meshes by file name (``Geometry.filename``, kept exactly as written):

* ``package://pkg/rel`` (ROS) and ``model://name/rel`` (SDF, Gazebo): ``rel`` inside the package's
  folder, looked up, in this order, in the folders given explicitly (``--package-path pkg=DIR``), in a
  folder named ``pkg`` above the robot file, and on the search paths of the environment
  (``ROS_PACKAGE_PATH``, ``AMENT_PREFIX_PATH``'s ``share/pkg``; for ``model://`` also
  ``GZ_SIM_RESOURCE_PATH``, ``IGN_GAZEBO_RESOURCE_PATH``, ``GAZEBO_MODEL_PATH``);
* ``file:///abs/path``, an absolute path, or a path relative to the robot file's folder (an MJCF's
  already joined with its ``meshdir`` by the reader).

A robot file is untrusted. Resolving only looks at file names (it opens nothing): a name must end in
a mesh suffix (:data:`MESH_SUFFIXES`, also after following symbolic links), ``package://`` and
``model://`` names may not climb out of their package with ``..``, nothing is fetched from the
network, and a file larger than :data:`MAX_MESH_BYTES` is refused. A file outside the robot file's
folder (``../meshes``, an absolute path, a symbolic link leading out), or a ``package://`` or
``model://`` file reached through a symbolic link leading out of its package, is used, and said once,
in one warning line for all of them.

:func:`copy_meshes` copies the resolved files into a folder beside an output file (an MJCF or URDF
that then loads from anywhere), converting formats the target cannot read (MuJoCo: .stl, .obj, .msh;
COLLADA .dae and .ply become binary .stl) with trimesh (``pip install 'robkin[meshes]'``).
"""

from __future__ import annotations

import os
import re
import shutil
import warnings
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import TYPE_CHECKING, Collection, Iterable, Mapping
from urllib.parse import unquote, urlparse

from .convert import to_stl

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["MeshFile", "MESH_SUFFIXES", "MUJOCO_MESH_SUFFIXES", "MAX_MESH_BYTES", "MAX_MESHES", "mesh_names",
           "resolve_mesh_file", "resolve_meshes", "missing_line", "copy_meshes", "with_mesh_names",
           "parse_package_path"]

#: Mesh file suffixes robkin uses (lower case; the file's suffix is compared case-insensitively).
MESH_SUFFIXES = (".stl", ".obj", ".dae", ".msh", ".ply")
#: The suffixes MuJoCo reads; copy_meshes converts the others to .stl.
MUJOCO_MESH_SUFFIXES = (".stl", ".obj", ".msh")
#: Largest mesh file used (a detailed arm link is a few MB; this bounds memory when one is read).
MAX_MESH_BYTES = 64 * 1024 * 1024
#: Most distinct mesh files of one robot (a humanoid has a few hundred).
MAX_MESHES = 1000
#: Longest file name looked at (a path longer than this exists on no file system robkin runs on).
MAX_NAME_CHARS = 4096

#: Environment variables holding search paths for each scheme's first component.
SEARCH_PATHS = {"package": ("ROS_PACKAGE_PATH",),
                "model": ("GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH", "GAZEBO_MODEL_PATH")}
#: A ROS package or Gazebo model name: letters, digits, '_', '-', '.' (but not '.' or '..' alone).
_PACKAGE_NAME = re.compile(r"[A-Za-z0-9_.\-]+")


@dataclass(frozen=True)
class MeshFile:
    """One mesh file name of a robot file and where it was found.

    source : the file name exactly as the robot file wrote it
    path : the file found (absolute, symbolic links resolved), or None
    reason : why it was not found or cannot be used (None when ``path`` is set)
    leaves_package : a ``package://`` or ``model://`` name whose file, after symbolic links, lies
        outside the package folder it was found in (used, and named in the warning line)
    """

    source: str
    path: Path | None
    reason: str | None
    leaves_package: bool = False


def _short(text: str, limit: int = 100) -> str:
    """``text`` cut to ``limit`` characters in the middle (the end of a path names the file)."""
    if len(text) <= limit:
        return text
    head = (limit - 3) // 2
    return text[:head] + "..." + text[len(text) - (limit - 3 - head):]


def mesh_names(robot: "Robot", roles: Collection[str] = ("visual", "collision")) -> list[str]:
    """The distinct mesh file names of ``robot.bodies.shapes`` (of the given roles), in order of first use."""
    bodies = getattr(robot, "bodies", None)
    names: dict[str, None] = {}
    for s in (bodies.shapes if bodies else ()):
        if s.role in roles and s.geometry.kind == "mesh" and s.geometry.filename is not None:
            names.setdefault(s.geometry.filename, None)
    return list(names)


def with_mesh_names(robot: "Robot", names: Mapping[str, str]) -> "Robot":
    """``robot`` with its shapes' mesh file names replaced by ``names`` (old -> new; others kept), e.g.
    the copies :func:`copy_meshes` made, for a writer that repeats the names (URDF)."""
    from dataclasses import replace

    bodies = getattr(robot, "bodies", None)
    if not bodies or not names:
        return robot
    shapes = tuple(replace(s, geometry=replace(s.geometry, filename=names[s.geometry.filename]))
                   if s.geometry.kind == "mesh" and s.geometry.filename in names else s for s in bodies.shapes)
    return robot.replace(bodies=replace(bodies, shapes=shapes))


def parse_package_path(text: str) -> tuple[str, Path]:
    """``NAME=DIR`` of ``--package-path`` -> (NAME, DIR); ValueError (one line) when malformed.

    ``text``: the option's value, ``NAME=DIR``.
    """
    name, sep, folder = text.partition("=")
    name = name.strip()
    if not sep or not folder or not _valid_package(name):
        raise ValueError(f"'{_short(text, 60)}' is not NAME=DIR (a package or model name, '=', its folder)")
    path = Path(folder).expanduser()
    if not path.is_dir():
        raise ValueError(f"'{_short(text, 60)}': {_short(folder, 60)} is not a folder")
    return name, path


def _valid_package(name: str) -> bool:
    return bool(_PACKAGE_NAME.fullmatch(name)) and name not in (".", "..")


def _package_roots(package: str, scheme: str, robot_file: Path,
                   package_paths: Mapping[str, Path]) -> list[Path]:
    """Folders that may be package (or model) ``package``, in the order they are tried."""
    roots = [Path(package_paths[package])] if package in package_paths else []
    folder = robot_file.resolve().parent
    roots += [d for d in (folder, *folder.parents) if d.name == package]
    for var in SEARCH_PATHS[scheme]:
        for entry in filter(None, os.environ.get(var, "").split(os.pathsep)):
            base = Path(entry)
            roots += [base] if base.name == package else [base / package]
    if scheme == "package":
        roots += [Path(e) / "share" / package for e in filter(None, os.environ.get("AMENT_PREFIX_PATH", "")
                                                                        .split(os.pathsep))]
    return [r for r in roots if _is_dir(r)]


def _is_dir(path: Path) -> bool:
    try:
        return path.is_dir()
    except (OSError, ValueError):  # a name too long for the file system, or holding a NUL
        return False


def _inside_parts(rel: str) -> tuple[str, ...] | None:
    """The parts of a /-separated relative name with '.' and '..' applied, or None if it climbs out."""
    parts: list[str] = []
    for part in rel.replace("\\", "/").split("/"):
        if part in ("", "."):
            continue
        if part == "..":
            if not parts:
                return None
            parts.pop()
        else:
            parts.append(part)
    return tuple(parts)


def _within(path: Path, root: Path) -> bool:
    """Whether the resolved ``path`` lies inside ``root`` (itself resolved: a linked package folder,
    colcon's ``--symlink-install``, is the folder it leads to)."""
    try:
        return path.is_relative_to(root.resolve())
    except (OSError, RuntimeError):  # pragma: no cover - a loop of links in the root
        return False


def _check_file(candidate: Path) -> tuple[Path | None, str | None]:
    """(real path, None) for a usable mesh file, else (None, why not). Looks at names and sizes only."""
    try:
        real = candidate.resolve()
        if not real.exists():
            return None, f"no such file {_short(str(candidate))}"
        if not real.is_file():
            return None, f"{_short(str(candidate))} is not a regular file"
        if real.suffix.lower() not in MESH_SUFFIXES:
            return None, f"{_short(str(candidate))} leads to {_short(real.name, 60)}, not a mesh file"
        if real.stat().st_size > MAX_MESH_BYTES:
            return None, f"{_short(str(candidate))} is larger than {MAX_MESH_BYTES // 2 ** 20} MB"
    except (OSError, RuntimeError, ValueError) as exc:  # too long, a loop of links, no permission, a NUL
        return None, f"{_short(str(candidate))} cannot be used ({type(exc).__name__})"
    return real, None


def resolve_mesh_file(filename: str, robot_file: str | os.PathLike,
                      package_paths: Mapping[str, Path] | None = None) -> MeshFile:
    """Find the one mesh file ``filename`` (as written in ``robot_file``); see the module doc.

    ``package_paths``: package name -> its folder (``--package-path NAME=DIR``), searched first.
    """
    robot_file = Path(robot_file)
    packages = dict(package_paths or {})
    if not filename:
        return MeshFile(filename, None, "no file name")
    if len(filename) > MAX_NAME_CHARS:
        return MeshFile(filename, None, f"file name longer than {MAX_NAME_CHARS} characters")
    url = urlparse(filename)
    scheme = url.scheme.lower()
    suffix = PurePosixPath(unquote(url.path).replace("\\", "/")).suffix.lower()
    if suffix not in MESH_SUFFIXES:
        return MeshFile(filename, None, f"'{_short(suffix or '(none)', 20)}' is not a mesh file type "
                                        f"({', '.join(MESH_SUFFIXES)})")
    if scheme in SEARCH_PATHS:
        package, rel = url.netloc, unquote(url.path)
        if not package:  # package:///pkg/rel (example-robot-data's Talos): pinocchio reads it so too
            package, _, rel = rel.lstrip("/").partition("/")
        if not _valid_package(package):
            return MeshFile(filename, None, f"'{_short(package, 40)}' is not a {scheme} name")
        parts = _inside_parts(rel)
        if not parts:
            return MeshFile(filename, None, f"leads outside {scheme} '{package}'" if parts is None
                            else "names no file")
        roots = _package_roots(package, scheme, robot_file, packages)
        if not roots:
            where = ", ".join(("a folder above the file",) + SEARCH_PATHS[scheme] +
                              (("AMENT_PREFIX_PATH",) if scheme == "package" else ()))
            return MeshFile(filename, None, f"{scheme} '{package}' not found (looked in {where}); "
                                            f"give its folder with --package-path {package}=DIR "
                                            f"(Python: package_paths={{'{package}': DIR}})")
        reason = None
        for root in roots:
            path, why = _check_file(root.joinpath(*parts))
            if path is not None:  # a link inside the package may lead out of it: used, said (_warn_outside)
                return MeshFile(filename, path, None, not _within(path, root))
            reason = reason or why
        return MeshFile(filename, None, f"not in {scheme} '{package}' ({reason})")
    if scheme == "file":
        if url.netloc not in ("", "localhost"):
            return MeshFile(filename, None, f"file://{_short(url.netloc, 40)}/ names another machine")
        path, why = _check_file(Path(unquote(url.path)))
    elif scheme == "" or len(scheme) == 1:  # a plain path (a Windows drive letter parses as a scheme)
        plain = Path(filename.replace("\\", "/")) if scheme == "" else Path(filename)
        path, why = _check_file(plain if plain.is_absolute() else robot_file.resolve().parent / plain)
    else:
        return MeshFile(filename, None, f"a {_short(scheme, 20)}:// address: nothing is fetched")
    return MeshFile(filename, path, why)


def resolve_meshes(robot: "Robot", source_file: str | os.PathLike,
                   package_paths: Mapping[str, Path] | None = None) -> dict[str, MeshFile]:
    """Every distinct mesh file name of ``robot.bodies.shapes`` -> where it is (see the module doc).

    Parameters
    ----------
    robot : Robot
        A robot read from ``source_file`` (its shapes' ``geometry.filename``).
    source_file : path
        The robot file; relative names are relative to its folder, ``package://`` is also looked up
        above it.
    package_paths : mapping NAME -> folder, optional
        Folders of packages (``package://NAME``) or models (``model://NAME``), tried first.

    Returns
    -------
    dict
        File name as written -> ``MeshFile`` (``path`` or ``reason``), in order of first use. Warns
        once (one line) when files outside the robot file's folder are used.
    """
    source_file = Path(source_file)
    out: dict[str, MeshFile] = {}
    names = mesh_names(robot)
    for k, name in enumerate(names):
        out[name] = (resolve_mesh_file(name, source_file, package_paths) if k < MAX_MESHES else
                     MeshFile(name, None, f"more than {MAX_MESHES} mesh files"))
    _warn_outside(out.values(), source_file)
    return out


def _warn_outside(found: Iterable[MeshFile], source_file: Path) -> None:
    try:
        folder = source_file.resolve().parent
    except OSError:  # pragma: no cover - a folder that vanished
        return
    found = list(found)
    # package:// and model:// files are outside the robot file's folder by design: said only when a
    # symbolic link inside the package leads out of it
    left = [m.source for m in found if m.path is not None and m.leaves_package]
    outside = [m.source for m in found if m.path is not None and (m.leaves_package or (
               urlparse(m.source).scheme.lower() not in SEARCH_PATHS and not m.path.is_relative_to(folder)))]
    if outside:
        more = f" and {len(outside) - 2} more" if len(outside) > 2 else ""
        where = "the model's folder or their package" if left else "the model's folder"
        warnings.warn(f"{_short(str(source_file), 80)}: {len(outside)} mesh file(s) outside {where} "
                      f"are used: {', '.join(_short(s, 60) for s in outside[:2])}{more}", UserWarning, stacklevel=3)


def missing_line(resolved: Mapping[str, MeshFile], source_file: str | os.PathLike) -> str | None:
    """One line saying which meshes were not found and why (grouped by reason), or None if none are missing.

    ``resolved``: mesh name -> ``MeshFile`` (``resolve_meshes``); ``source_file``: the robot file, named at
    the line's start.
    """
    by_reason: dict[str, list[str]] = {}
    for m in resolved.values():
        if m.path is None:
            by_reason.setdefault(m.reason or "not found", []).append(m.source)
    if not by_reason:
        return None
    count = sum(len(v) for v in by_reason.values())
    groups = [f"{_short(names[0], 70)}{f' and {len(names) - 1} more' if len(names) > 1 else ''}: "
              f"{_short(reason, 240)}" for reason, names in list(by_reason.items())[:3]]
    more = f"; {len(by_reason) - 3} other reasons" if len(by_reason) > 3 else ""
    return (f"{_short(str(source_file), 80)}: {count} of {len(resolved)} mesh files not found, drawn without "
            f"them: {'; '.join(groups)}{more}")


def copy_meshes(resolved: Mapping[str, MeshFile], out_dir: str | os.PathLike, subdir: str = "meshes", *,
                readable: Collection[str] | None = MUJOCO_MESH_SUFFIXES) -> dict[str, str]:
    """Copy the found mesh files into ``out_dir/subdir``; returns source name -> path relative to ``out_dir``.

    Each file is copied once (names made unique on collisions: ``base.stl``, ``base_2.stl``); a file
    already in place (the output folder is the model's) is not copied again, and a file of the model
    is never overwritten. InputError (one line naming the path, nothing written) when ``out_dir/subdir``
    is, or lies under, a symbolic link leading outside ``out_dir``. Formats not in ``readable``
    (default: what MuJoCo reads; None keeps every format) are converted to binary .stl with trimesh;
    without trimesh, or when a file cannot be converted, those meshes are left out of the result with
    one warning line naming them.
    Meshes not found (``path`` None) are left out as well.

    ``resolved``: mesh name -> ``MeshFile`` (``resolve_meshes``); the ones not found are skipped.
    """
    from ..files.atomic import check_inside

    out = Path(out_dir)
    folder = out / subdir
    sources = {m.path for m in resolved.values() if m.path is not None}
    if sources:  # before anything is written: never through a link leading out of the output folder
        check_inside(out, folder)
    taken: set[str] = set()
    done: dict[Path, str | None] = {}
    result: dict[str, str] = {}
    skipped: list[str] = []
    for name, mesh in resolved.items():
        if mesh.path is None:
            continue
        if mesh.path not in done:
            done[mesh.path] = _copy_one(mesh.path, folder, subdir, sources, taken, readable, skipped)
        if done[mesh.path] is not None:
            result[name] = done[mesh.path]  # type: ignore[assignment]
    if skipped:
        more = f" and {len(skipped) - 3} more" if len(skipped) > 3 else ""
        warnings.warn(f"{len(skipped)} mesh file(s) left out: {'; '.join(skipped[:3])}{more}",
                      UserWarning, stacklevel=2)
    return result


def _copy_one(path: Path, folder: Path, subdir: str, sources: set[Path], taken: set[str],
              readable: Collection[str] | None, skipped: list[str]) -> str | None:
    """Copy (or convert) one file; its name relative to the output folder, or None (added to ``skipped``)."""
    convert = readable is not None and path.suffix.lower() not in readable
    data: bytes | None = None
    if convert:
        data = to_stl(path, skipped)
        if data is None:
            return None
    suffix = ".stl" if convert else path.suffix
    stem = re.sub(r"[^A-Za-z0-9_.\-]", "_", path.stem) or "mesh"
    k = 1
    while True:
        target = folder / f"{stem}{'' if k == 1 else f'_{k}'}{suffix}"
        key = target.name.lower()  # one name per file also on case-insensitive file systems
        k += 1
        if key in taken:
            continue
        try:
            real = target.resolve() if target.exists() else None
        except OSError:  # pragma: no cover - a loop of symbolic links where the file would go
            continue
        if real is not None and real == path and not convert:
            taken.add(key)
            return f"{subdir}/{target.name}"  # already in place: the output folder is the model's
        if real is not None and real in sources:
            continue  # a mesh of the model itself: never overwritten
        taken.add(key)
        break
    from ..files.atomic import atomic_file

    folder.mkdir(parents=True, exist_ok=True)
    with atomic_file(target, binary=True) as f:
        if data is not None:
            f.write(data)
        else:
            with open(path, "rb") as src:
                shutil.copyfileobj(src, f)
    return f"{subdir}/{target.name}"
