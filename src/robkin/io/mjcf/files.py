"""An MJCF model with its meshes: the writer (``writer``) and the mesh files (``io.meshes.files``) together.

``write_mjcf(robot, "out/robot.xml", source="robot.urdf")`` is what ``robkin convert --to mjcf -o``
does, for Python: the robot file's meshes found (``package://``, ``model://``, relative paths, the
``package_paths`` given), copied into ``out/meshes`` (COLLADA and PLY converted to STL, an STL beyond
MuJoCo's triangle limit to OBJ; a COLLADA visual of several colours also split into one STL per colour,
``mesh_parts``), and the model written atomically beside them, naming them relative to
itself so that the folder loads from anywhere.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Mapping, Sequence

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["mjcf_with_meshes", "write_mjcf"]


def mjcf_with_meshes(robot: Robot, source: str | os.PathLike[str] | None, out_dir: Path | None, *,
                     mesh_dir: str = "meshes", package_paths: Mapping[str, Path] | None = None,
                     premade: Mapping[str, str] | None = None,
                     contact_excludes: Callable[[str], Sequence[tuple[str, str]]] | None = None,
                     **options: Any) -> str:
    """The MJCF text of ``robot`` (read from the robot file ``source``; None: no meshes to find).

    With ``out_dir``, the meshes are copied into ``out_dir/mesh_dir`` first and named relative to
    ``out_dir``; without it, the found meshes MuJoCo reads are named by their absolute paths. Meshes
    not found are left out with one warning line. ``options``: those of ``writer.mjcf_text``
    (``actuators``, ``kp``, ``kv``, ``home``, ``gravcomp``, ``servos``, ``fuse_fixed``).

    ``premade``: mesh names of shapes whose files are already in ``out_dir`` (made by
    ``robkin.collision``) -> their paths relative to it: named as such, never looked for in the source.
    ``contact_excludes``: a function of the model's draft text giving the body pairs to exclude from
    contact (``robkin.collision.exclusions``), written into the final text.
    InputError (one line) when the robot has visual shapes and none of them could be written: the model
    would render empty.
    """
    from .writer import mjcf_text

    premade = dict(premade or {})
    mesh_files: dict[str, str] = dict(premade)
    mesh_parts: dict[str, list[tuple[str, tuple[float, ...]]]] = {}
    found_in = robot
    if premade:
        from dataclasses import replace

        found_in = robot.replace(bodies=replace(robot.bodies, shapes=tuple(
            s for s in robot.bodies.shapes if s.geometry.filename not in premade)))
    if source is not None and any(s.geometry.kind == "mesh" for s in found_in.bodies.shapes):
        from ..meshes.files import MUJOCO_MESH_SUFFIXES, copy_meshes, missing_line, resolve_meshes

        resolved = resolve_meshes(found_in, source, package_paths)
        missing = missing_line(resolved, source)
        if missing:
            warnings.warn(missing.replace("drawn without them", "left out of the MJCF"), UserWarning, stacklevel=2)
        if out_dir is not None:
            from .meshes import fit_for_mujoco

            from .mesh_parts import visual_mesh_parts

            sources = {m.path.resolve() for m in resolved.values() if m.path is not None}
            mesh_files = fit_for_mujoco(copy_meshes(resolved, out_dir, mesh_dir), out_dir, sources) | premade
            # COLLADA visuals in their own colours, where the source gives the shape none
            uncoloured = {s.geometry.filename for s in robot.bodies.shapes if s.role == "visual"
                          and s.geometry.kind == "mesh" and (s.material is None or s.material.rgba is None)}
            visual = {k: m.path for k, m in resolved.items() if k in uncoloured and m.path is not None}
            parts = visual_mesh_parts(visual, out_dir, mesh_dir)
            for name, items in parts.items():
                fitted = fit_for_mujoco({f"{name}#{k}": f for k, (f, _) in enumerate(items)}, out_dir, sources)
                if len(fitted) == len(items):
                    mesh_parts[name] = [(fitted[f"{name}#{k}"], rgba) for k, (_, rgba) in enumerate(items)]
            _drop_unused(robot, mesh_files, mesh_parts, out_dir, sources)
        else:  # a model without a folder: the files where they are, in the formats MuJoCo reads
            mesh_files = {k: str(v.path) for k, v in resolved.items()
                          if v.path is not None and v.path.suffix.lower() in MUJOCO_MESH_SUFFIXES}
    text = mjcf_text(robot, mesh_files=mesh_files, mesh_parts=mesh_parts, **options)
    _refuse_empty(robot, text, source, out_dir)
    if contact_excludes is not None:
        pairs = contact_excludes(text)
        if pairs:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # said by the draft already
                text = mjcf_text(robot, mesh_files=mesh_files, mesh_parts=mesh_parts, contact_excludes=pairs,
                                 **options)
    return text


def _refuse_empty(robot: Robot, text: str, source: str | os.PathLike[str] | None, out_dir: Path | None) -> None:
    """InputError when the robot has visual shapes and the model has no visual geom (MuJoCo would show
    nothing: its collision geoms are hidden by default)."""
    visuals = [s for s in robot.bodies.shapes if s.role == "visual"]
    if not visuals or '<geom class="visual"' in text:
        return
    from ...errors import InputError

    try:
        import trimesh  # noqa: F401
        hint = "see the warnings above"
        if out_dir is None:
            hint = "write it with -o DIR/robot.xml: COLLADA and PLY meshes are then converted into DIR/meshes"
    except ImportError:
        hint = "COLLADA (.dae) and PLY meshes are converted with trimesh: pip install 'robkin[meshes]'"
    raise InputError(f"none of the {len(visuals)} visual shape(s) could be written, so the model would render "
                     f"empty ({hint})", source=None if source is None else str(source))


def _drop_unused(robot: Robot, mesh_files: dict[str, str], mesh_parts: Mapping[str, object], out_dir: Path,
                 sources: set[Path]) -> None:
    """Remove the single-colour copy of a mesh that is drawn only in parts (no other shape uses it)."""
    used = {mesh_files[s.geometry.filename] for s in robot.bodies.shapes
            if s.geometry.kind == "mesh" and s.geometry.filename in mesh_files
            and not (s.role == "visual" and s.geometry.filename in mesh_parts
                     and (s.material is None or s.material.rgba is None))}
    for name in mesh_parts:
        written = mesh_files[name]
        path = out_dir / written
        if written not in used and path.exists() and path.resolve() not in sources:
            path.unlink()


def write_mjcf(robot: Robot, path: str | os.PathLike[str], *, source: str | os.PathLike[str] | None = None,
               package_paths: Mapping[str, Path] | None = None, **options: Any) -> Path:
    """Write ``robot`` as an MJCF model at ``path`` with its meshes in a ``meshes`` folder beside it
    (see the module doc); returns the path.

    Parameters
    ----------
    robot : Robot
    path : str or path
        The model file. Its folder is made if need be, inside an existing folder (as ``robkin convert
        -o`` does); if the model cannot be written, a folder made here is removed again.
    source : str or path, optional
        The robot file the robot was read from: its meshes are found from there (None: no meshes).
    package_paths : mapping of package name to folder, optional
        Where ``package://NAME/...`` meshes are (``--package-path NAME=DIR`` on the command line);
        searched before the folders above ``source``, ``ROS_PACKAGE_PATH`` and ``AMENT_PREFIX_PATH``.
    **options
        Those of ``writer.mjcf_text`` (``actuators``, ``kp``, ``kv``, ``home``, ``gravcomp``, ``servos``,
        ``fuse_fixed``).

    Returns
    -------
    Path
        ``path``.
    """
    import shutil

    from ..files.atomic import write_text_atomic

    out = Path(path)
    folder = out.parent if str(out.parent) else Path(".")
    made = not folder.exists() and (folder.parent if str(folder.parent) else Path(".")).is_dir()
    if made:
        folder.mkdir()
    try:
        text = mjcf_with_meshes(robot, source, folder, package_paths=package_paths, **options)
        write_text_atomic(out, text)
    except BaseException:
        if made:    # the meshes copied into it are this call's: nothing half-written is left
            shutil.rmtree(folder, ignore_errors=True)
        raise
    return out
