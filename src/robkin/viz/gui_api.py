"""What the browser GUI asks of the library, as plain functions on text: parse, describe, export.

The server (``gui.py``) is stateless: every request carries the robot text the user typed, pasted or
loaded, so there is nothing to get out of sync and a reload never loses work. Every function raises
only :class:`~robkin.errors.InputError` for bad input; the server turns that into a message in the
page.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from ..errors import InputError
from ..robot import Robot

__all__ = ["INPUT_FORMATS", "EXPORTS", "parse_robot", "describe", "export", "MAX_TEXT"]

INPUT_FORMATS = ("auto", "yaml", "json", "urdf", "dh-rows", "mdh-rows", "rpy-rows")
#: Download name -> (document sections or None for URDF / the full document, file suffix, MIME type).
EXPORTS: dict[str, tuple[tuple[str, ...] | None, str, str]] = {
    "yaml": (None, ".yaml", "application/yaml"),
    "json": (None, ".json", "application/json"),
    "urdf": (None, ".urdf", "application/xml"),
    "dh": (("dh",), "_dh.yaml", "application/yaml"),
    "mdh": (("mdh",), "_mdh.yaml", "application/yaml"),
    "hayati": (("hayati",), "_hayati.yaml", "application/yaml"),
    "poe": (("poe",), "_poe.yaml", "application/yaml"),
    "poe-body": (("poe_body",), "_poe_body.yaml", "application/yaml"),
    "rpy-xyz": (("rpy_xyz",), "_rpy_xyz.yaml", "application/yaml"),
    "gjd": (("gjd",), "_gjd.yaml", "application/yaml"),
}
#: Largest robot text accepted (a URDF of a humanoid is a few hundred kB; this bounds memory per request).
MAX_TEXT = 4 * 1024 * 1024


def _detect(text: str) -> str:
    s = text.lstrip("\ufeff \t\r\n")
    if s.startswith("<"):
        return "urdf"
    if s.startswith("{"):
        return "json"
    return "yaml"


def parse_robot(text: str, fmt: str = "auto", base_link: str | None = None, tip_link: str | None = None,
                source: str = "input") -> tuple[Robot, list[str]]:
    """A Robot from document text (YAML/JSON) or URDF XML, and the warnings raised while reading it.

    Parameters
    ----------
    text : str
        The robot as typed or pasted.
    fmt : {'auto', 'yaml', 'json', 'urdf', 'dh-rows', 'mdh-rows', 'rpy-rows'}
        'auto' takes text starting with '<' as URDF and with '{' as JSON, else YAML. The '-rows'
        formats are bare tables, one row per line (see ``robkin.viz.table_text``).
    base_link, tip_link : str, optional
        URDF only: the serial chain to take from a tree.
    source : str
        Where the text came from, to start error messages with (a file name, or "input").
    """
    if not isinstance(text, str) or not text.strip():
        raise InputError("input: empty; paste or load a robot document (YAML/JSON) or a URDF")
    if len(text) > MAX_TEXT:
        raise InputError(f"input: {len(text)} characters; at most {MAX_TEXT} accepted")
    if fmt not in INPUT_FORMATS:
        raise InputError(f"format: '{fmt}' is not one of {', '.join(INPUT_FORMATS)}")
    kind = _detect(text) if fmt == "auto" else fmt
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if kind == "urdf":
            if not text.lstrip("\ufeff \t\r\n").startswith("<"):
                raise InputError("urdf: expected XML starting with '<' (a <robot> element)")
            from ..io.urdf import robot_from_urdf

            try:
                robot = robot_from_urdf(text.lstrip("\ufeff \t\r\n"), base_link=base_link or None,
                                        tip_link=tip_link or None)
            except InputError as exc:
                # The page's fields are called "base link" / "tip link", not the CLI options.
                msg = (str(exc).removeprefix("<urdf string>: ").replace("--base-link", "base link")
                       .replace("--tip-link", "tip link"))
                raise InputError(msg if msg.startswith(source) else f"{source}: {msg}") from None
        else:
            if base_link or tip_link:
                raise InputError("base/tip link: apply to URDF input only")
            from ..io.document import parse_document

            if kind.endswith("-rows"):
                import json

                from .table_text import document_from_table

                try:
                    text, kind = json.dumps(document_from_table(text, kind)), "json"
                except InputError as exc:
                    raise exc.in_source(source) from None
            robot = parse_document(text, kind, source=source)
    return robot, [str(w.message) for w in caught if issubclass(w.category, Warning)]


def _q_of(robot: Robot, q: Any, strict: bool = True) -> np.ndarray:
    if q is None or (not strict and isinstance(q, (list, tuple)) and len(q) != robot.n):
        return np.zeros(robot.n)  # no q, or q of a robot the user has just edited into another one
    if not isinstance(q, (list, tuple)) or len(q) != robot.n:
        raise InputError(f"q: expected {robot.n} numbers (one per joint)")
    try:
        Q = np.array([float(v) for v in q])
    except (TypeError, ValueError):
        raise InputError("q: expected numbers") from None
    if not np.all(np.isfinite(Q)):
        raise InputError("q: contains NaN or infinity")
    return Q


def _finite(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def describe(text: str, fmt: str = "auto", q: Any = None, base_link: str | None = None,
             tip_link: str | None = None, strict_q: bool = True, overlay: Any = None) -> dict[str, Any]:
    """Everything the page shows for a robot at q: joints, all representations, URDF, pose, geometry.

    Returns a JSON-ready dict: ``name``, ``n``, ``joints`` (name, type, lower, upper, flip), ``scale``,
    ``q``, ``document`` (the robot document with all sections, as ``robkin convert --to json``
    writes it), ``urdf`` (text, or null with ``urdf_error``), ``T`` (tool pose at q, 4x4), ``rpy_xyz``
    (tool pose as roll, pitch, yaw, x, y, z), ``scene`` (geometry to draw, see ``Scene.to_json``) and
    ``warnings`` (inputs projected onto valid values). With ``strict_q`` false, a q of the wrong
    length (the user edited the robot into one with another joint count) means home instead of an
    error. ``overlay`` lists representations (``robkin.viz.scene.REPRESENTATIONS``) to rebuild the robot
    from and draw on top: their scenes come back as ``overlays`` and by how much they and the robot
    disagree as ``agreement`` {position, rotation, axes} (rounding-size for a correct conversion).
    """
    from .. import se3
    from ..io.document import document_from_robot
    from .scene import build_scene

    robot, notes = parse_robot(text, fmt, base_link, tip_link)
    Q = _q_of(robot, q, strict_q)
    T = robot.fk(Q)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        doc = document_from_robot(robot)
    notes += [str(w.message) for w in caught]
    urdf, urdf_error = _urdf_text(robot)
    scene = build_scene(robot, Q)
    overlays, agreement = _overlays(robot, Q, scene, overlay)
    return {
        "name": robot.name or "",
        "n": robot.n,
        "joints": [{"name": j.name, "type": j.type, "lower": _finite(lim[0]), "upper": _finite(lim[1]),
                    "flip": j.flip} for j, lim in zip(robot.joints, robot.limits)],
        "scale": robot.scale,
        "q": Q.tolist(),
        "document": doc,
        "urdf": urdf,
        "urdf_error": urdf_error,
        "T": T.tolist(),
        "rpy_xyz": np.concatenate([se3.rpy_from_matrix(T[:3, :3]), T[:3, 3]]).tolist(),
        "scene": scene.to_json(),
        "overlays": overlays,
        "agreement": agreement,
        "warnings": notes,
    }


def _overlays(robot: Robot, Q: np.ndarray, scene: Any, overlay: Any) -> tuple[list[dict], dict | None]:
    from .scene import REPRESENTATIONS, disagreement, overlay_scenes

    if not overlay:
        return [], None
    if not isinstance(overlay, (list, tuple)) or not all(isinstance(r, str) for r in overlay):
        raise InputError(f"overlay: expected a list of names from {', '.join(REPRESENTATIONS)}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # conversion notes are shown once, with the tables
        scenes = overlay_scenes(robot, Q, list(overlay))
    pos, rot, axes = disagreement([scene, *scenes])
    return [s.to_json() for s in scenes], {"position": pos, "rotation": rot, "axes": axes}


def _urdf_text(robot: Robot) -> tuple[str | None, str | None]:
    try:
        from ..io.urdf import urdf_from_robot
    except ImportError:  # pragma: no cover - URDF support is part of robkin; kept for partial installs
        return None, "URDF export is not available in this installation"
    try:
        return urdf_from_robot(robot), None
    except InputError as exc:
        return None, str(exc)


def export(text: str, fmt: str, to: str, base_link: str | None = None, tip_link: str | None = None
           ) -> tuple[str, str, str]:
    """A download of the robot: (file name, MIME type, content).

    ``to`` is one of EXPORTS: the full document as 'yaml' or 'json', 'urdf', or one representation
    as a YAML document holding ``joints`` and that section only.
    """
    from ..io.document import document_from_robot, dump

    if to not in EXPORTS:
        raise InputError(f"download: '{to}' is not one of {', '.join(EXPORTS)}")
    robot, _ = parse_robot(text, fmt, base_link, tip_link)
    sections, suffix, mime = EXPORTS[to]
    stem = _safe_stem(robot.name or "robot")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # already shown by describe()
        if to == "urdf":
            from ..io.urdf import urdf_from_robot

            content = urdf_from_robot(robot)
        elif sections is None:
            content = dump(document_from_robot(robot), to)
        else:
            content = dump(document_from_robot(robot, sections), "yaml")
    return stem + suffix, mime, content


def _safe_stem(name: str) -> str:
    """A file name stem from a robot name: letters, digits, '-', '_' and '.' only."""
    stem = "".join(c if c.isalnum() or c in "-_." else "_" for c in name).strip("._")
    return stem[:64] or "robot"
