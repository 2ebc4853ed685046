"""What the browser GUI asks of the library, as plain functions on text: parse, describe, IK, export.

The server (``gui.py``) is stateless: every request carries the robot text the user typed, pasted or
loaded, so there is nothing to get out of sync and a reload never loses work. Parsing is memoised
(a few recent texts), so that dragging the tool frame, which asks for IK 30+ times a second, does
not re-read a URDF each time. Every function raises only :class:`~robkin.errors.InputError` for bad
input; the server turns that into a message in the page.
"""

from __future__ import annotations

import functools
import math
import warnings
from typing import Any, Mapping

import numpy as np

from ..errors import InputError, quote
from ..representations.registry import LiveMapping
from ..robot import Robot

__all__ = ["INPUT_FORMATS", "EXPORTS", "parse_robot", "describe", "solve_ik", "collision_at", "export", "MAX_TEXT"]

INPUT_FORMATS = ("auto", "yaml", "json", "urdf", "mjcf", "sdf", "dh-rows", "mdh-rows", "poe-rows", "rpy-rows")
#: XML robot formats: root element -> format (anything else starting with '<' is taken as URDF).
_XML_ROOTS = {"mujoco": "mjcf", "sdf": "sdf"}
def _exports() -> dict[str, tuple[tuple[str, ...] | None, str, str]]:
    """Download name -> (document sections or None for URDF / the full document, file suffix, MIME
    type): the whole document, the URDF, and each registered representation's section alone
    (``robkin.representations.registry``)."""
    from ..representations.registry import representations

    return {"yaml": (None, ".yaml", "application/yaml"), "json": (None, ".json", "application/json"),
            "urdf": (None, ".urdf", "application/xml"),
            **{r.name: ((r.section,), f"_{r.section}.yaml", "application/yaml") for r in representations()
               if "yaml" in r.file_formats}}


#: The downloads (``_exports``), a live view of the registry.
EXPORTS: Mapping[str, tuple[tuple[str, ...] | None, str, str]] = LiveMapping(_exports)
#: Largest robot text accepted (a URDF of a humanoid is a few hundred kB; this bounds memory per request).
MAX_TEXT = 4 * 1024 * 1024


def _detect(text: str) -> str:
    s = text.lstrip("\ufeff \t\r\n")
    if s.startswith("<"):
        import re

        root = re.search(r"<([A-Za-z_][\w.-]*)", re.sub(r"<[?!][^>]*>", "", s[:4096]))  # skip <?xml?>, comments
        return _XML_ROOTS.get(root.group(1) if root else "", "urdf")
    if s.startswith("{"):
        return "json"
    return "yaml"


def parse_robot(text: str, fmt: str = "auto", base_link: str | None = None, tip_link: str | None = None,
                source: str = "input", tool_row: bool = False) -> tuple[Robot, list[str]]:
    """A Robot from document text (YAML/JSON) or URDF XML, and the warnings raised while reading it.

    Parameters
    ----------
    text : str
        The robot as typed or pasted.
    fmt : {'auto', 'yaml', 'json', 'urdf', 'dh-rows', 'mdh-rows', 'poe-rows', 'rpy-rows'}
        'auto' takes text starting with '<' as URDF and with '{' as JSON, else YAML. The '-rows'
        formats are bare tables, one row per line (see ``robkin.viz.table_text``).
    base_link, tip_link : str, optional
        URDF only: the serial chain to take from a tree.
    source : str
        Where the text came from, to start error messages with (a file name, or "input").
    tool_row : bool
        DH / modified DH rows: the last row is the fixed tool (flange) transform, not a joint.
    """
    if not isinstance(text, str) or not text.strip():
        raise InputError("input: empty; paste or load a robot document (YAML/JSON) or a URDF")
    if len(text) > MAX_TEXT:
        raise InputError(f"input: {len(text)} characters; at most {MAX_TEXT} accepted")
    if fmt not in INPUT_FORMATS:
        raise InputError(f"format: {quote(fmt)} is not one of {', '.join(INPUT_FORMATS)}")
    kind = _detect(text) if fmt == "auto" else fmt
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if kind in ("urdf", "mjcf", "sdf"):
            if not text.lstrip("\ufeff \t\r\n").startswith("<"):
                root = {"urdf": "robot", "mjcf": "mujoco", "sdf": "sdf"}[kind]
                raise InputError(f"{kind}: expected XML starting with '<' (a <{root}> element)")
            from ..io.mjcf.reader import robot_from_mjcf
            from ..io.sdf.reader import robot_from_sdf
            from ..io.urdf import robot_from_urdf
            from ..messages import render_options

            read = {"urdf": robot_from_urdf, "mjcf": robot_from_mjcf, "sdf": robot_from_sdf}[kind]
            try:
                robot = read(text.lstrip("\ufeff \t\r\n"), base_link=base_link or None, tip_link=tip_link or None)
            except InputError as exc:
                # The page's fields are called "base link" / "tip link", not the CLI options.
                msg = render_options(str(exc).removeprefix(f"<{kind} string>: "),
                                     {"base_link": "base link", "tip_link": "tip link"})
                raise InputError(msg if msg.startswith(source) else f"{source}: {msg}") from None
        else:
            if base_link or tip_link:
                raise InputError("base/tip link: apply to URDF, MJCF and SDF input only")
            from ..io.documents.reader import parse_document

            if kind.endswith("-rows"):
                import json

                from .table_text import document_from_table

                try:
                    text, kind = json.dumps(document_from_table(text, kind, tool_row)), "json"
                except InputError as exc:
                    raise exc.in_source(source) from None
            robot = parse_document(text, kind, source=source)
    return robot, [str(w.message) for w in caught if issubclass(w.category, Warning)]


@functools.lru_cache(maxsize=8)
def _parsed(text: str, fmt: str, base_link: str | None, tip_link: str | None, tool_row: bool
            ) -> tuple[Robot, tuple[str, ...], tuple[str, ...]]:
    """parse_robot, memoised: (robot, warnings, URDF link names). Robot is immutable, so sharing is safe."""
    robot, notes = parse_robot(text, fmt, base_link, tip_link, tool_row=tool_row)
    links: tuple[str, ...] = ()
    if (_detect(text) if fmt == "auto" else fmt) == "urdf":
        from ..io.urdf import parse_urdf_text

        links = parse_urdf_text(text.lstrip("\ufeff \t\r\n")).links
    return robot, tuple(notes), links


def _robot(text: Any, fmt: Any, base_link: Any = None, tip_link: Any = None, tool_row: Any = False
           ) -> tuple[Robot, list[str], tuple[str, ...]]:
    """(robot, warnings, URDF link names) of request fields, memoised; wrong JSON types are input errors."""
    fmt, base_link, tip_link = fmt or "auto", base_link or None, tip_link or None
    for field, value in (("text", text), ("format (fmt)", fmt), ("base link", base_link), ("tip link", tip_link)):
        if not (isinstance(value, str) or (value is None and field.endswith("link"))):  # each field named
            raise InputError(f"{field}: expected a string, got {type(value).__name__}")
    if len(text) > MAX_TEXT:  # before the cache hashes it
        raise InputError(f"input: {len(text)} characters; at most {MAX_TEXT} accepted")
    robot, notes, names = _parsed(text, fmt, base_link, tip_link, tool_row is True)
    return robot, list(notes), names


def _q_of(robot: Robot, q: Any, strict: bool = True, field: str = "q") -> np.ndarray:
    """Joint values from a request field: n finite numbers (as ``robkin.io.files.numbers.number`` reads them)."""
    from ..io.files.numbers import number

    if q is None or (not strict and isinstance(q, (list, tuple)) and len(q) != robot.n):
        return robot.home()  # no q, or q of a robot the user has just edited into another one: its home
    if not isinstance(q, (list, tuple)) or len(q) != robot.n:
        raise InputError(f"{field}: expected {robot.n} numbers (one per joint)")
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in q):
        raise InputError(f"{field}: expected numbers")
    return np.array([number(v, f"{field}[{i}]") for i, v in enumerate(q)])


def _matrix_of(value: Any, field: str) -> np.ndarray:
    """A 4x4 matrix of finite numbers from a request field (lists of 4 rows of 4 numbers)."""
    from ..io.files.numbers import number

    rows = value if isinstance(value, (list, tuple)) and len(value) == 4 else None
    if rows is None or not all(isinstance(r, (list, tuple)) and len(r) == 4 for r in rows) or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for r in rows for v in r):
        raise InputError(f"{field}: expected a 4x4 matrix of numbers")
    return np.array([[number(v, f"{field}[{i}][{j}]") for j, v in enumerate(r)] for i, r in enumerate(rows)])


def _finite(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def describe(text: str, fmt: str = "auto", q: Any = None, base_link: str | None = None,
             tip_link: str | None = None, strict_q: bool = True, overlay: Any = None, tool_row: bool = False,
             other: Any = None, collision: bool = False) -> dict[str, Any]:
    """Everything the page shows for a robot at q: joints, all representations, URDF, pose, geometry.

    Returns a JSON-ready dict: ``name``, ``n``, ``joints`` (name, type, lower, upper, flip), ``scale``,
    ``q``, ``home`` (``Robot.home()``: q = 0 clipped into the limits, the MJCF keyframe's), ``document`` (the robot document with all sections, as ``robkin convert --to json``
    writes it), ``urdf`` (text, or null with ``urdf_error``), ``T`` (tool pose at q, 4x4), ``rpy_xyz``
    (tool pose as roll, pitch, yaw, x, y, z), ``scene`` (geometry to draw, see ``Scene.to_json``) and
    ``warnings`` (inputs projected onto valid values). With ``strict_q`` false, a q of the wrong
    length (the user edited the robot into one with another joint count) means home (``Robot.home()``)
    instead of an error. ``overlay`` lists representations (``robkin.viz.scene.REPRESENTATIONS``) to rebuild the robot
    from and draw on top: their scenes come back as ``overlays`` and by how much they and the robot
    disagree as ``agreement`` {position, rotation, axes} (rounding-size for a correct conversion).
    ``links`` lists a URDF's link names (the candidates for base and tip link). ``other`` (a dict of
    text, fmt, base_link, tip_link, tool_row, and ``exaggerate``, a factor from 1 to 1e6) is a second
    description to compare with: ``check`` holds its scene at the same q (its differences from the
    robot multiplied by ``exaggerate``, see ``robkin.viz.difference``), the difference ``arrows``
    (true distances), and ``robkin check``'s diagnosis of the whole robot, kinematics and mass
    properties (``robkin.viz.check_view.check_other``). ``collision`` true: ``collision`` says which
    links collide with each other at q (``robkin.viz.collision_api.collision_answer``), else it is null.
    """
    from .. import se3
    from ..io.documents.reader import document_from_robot
    from .check_view import check_other
    from .scene import build_scene

    robot, notes, links = _robot(text, fmt, base_link, tip_link, tool_row)
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
        "home": robot.home().tolist(),
        "document": doc,
        "urdf": urdf,
        "urdf_error": urdf_error,
        "T": T.tolist(),
        "rpy_xyz": np.concatenate([se3.rpy_from_matrix(T[:3, :3]), T[:3, 3]]).tolist(),
        "scene": scene.to_json(),
        "overlays": overlays,
        "agreement": agreement,
        "links": list(links),
        "motions": _motions(robot, Q),
        **_arm_angle(robot, Q),
        "check": None if other is None else check_other(robot, Q, other, _robot),
        "collision": _collision(robot, Q, collision, text, fmt, base_link, tip_link, tool_row),
        "warnings": notes,
    }


def _motions(robot: Robot, Q: np.ndarray) -> list | None:
    """Motion of each body from home to Q ((n+1) 4x4), to place the robot's visuals; None without any."""
    bodies = getattr(robot, "bodies", None)
    if not bodies or not bodies.visuals():
        return None
    from ..bodies import body_motions  # type: ignore[import-not-found, unused-ignore]

    return body_motions(robot, Q).tolist()


def solve_ik(text: str, fmt: str, target: Any, q0: Any, base_link: str | None = None,
             tip_link: str | None = None, tool_row: bool = False, arm_angle: Any = None,
             collision: bool = False) -> dict[str, Any]:
    """Joint values putting the tool at ``target`` (4x4), started from ``q0`` (the configuration shown).

    One IK attempt (no random restarts: dragging asks 30+ times a second and each answer seeds the
    next), with every closed-form branch when the robot has a closed form. Returns ``q`` (the nearest
    solution, or where the numeric method got closest; ``q0`` when no configuration exists),
    ``success``, ``position_error`` / ``orientation_error`` (length units / rad), ``message``,
    ``at_limit`` (indices of joints on a limit), ``solutions`` (all branches found), and at ``q``
    the tool pose ``T``, its ``rpy_xyz`` and the ``scene`` to draw. ``arm_angle`` (radians, SRS arms
    only): solve at that arm angle, on q0's branch (``kinematics.srs``); the answer's ``srs`` and
    ``arm_angle`` say whether the arm is SRS and the arm angle of ``q``. ``collision`` true: the
    answer's ``collision`` says which links collide at ``q`` (as ``describe``'s).

    ``text``, ``fmt``: the robot, as the page holds it (a robot file's text and its format, 'auto' to guess);
    ``base_link``, ``tip_link``: its chain; ``tool_row``: a table's last row is the tool, not a joint.
    """
    from .. import se3
    from .scene import build_scene

    robot, _, _ = _robot(text, fmt, base_link, tip_link, tool_row)
    Q0 = _q_of(robot, q0, field="q0")
    T = _matrix_of(target, "target")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a dragged target is projected onto a rotation silently
        if arm_angle is None:
            res = robot.ik(T, q0=Q0, restarts=0, all_solutions=True)
        else:
            if not (isinstance(arm_angle, (int, float)) and not isinstance(arm_angle, bool)
                    and np.isfinite(arm_angle)):
                raise InputError(f"arm_angle: expected a finite number of radians, got {arm_angle!r}")
            res = robot.ik(T, q0=Q0, arm_angle=float(arm_angle), all_solutions=True)
    q = np.asarray(res.q, dtype=float)
    found = bool(np.all(np.isfinite(q)))
    q = q if found else Q0
    lim = robot.limits
    # 1e-9 (rad or length units): IK clips onto a limit exactly; a joint this close is "on" it
    at_limit = np.flatnonzero((np.abs(q - lim[:, 0]) <= 1e-9) | (np.abs(q - lim[:, 1]) <= 1e-9))
    T_q = robot.fk(q)
    sols = [] if res.solutions is None else [s.tolist() for s in np.atleast_2d(res.solutions) if np.all(np.isfinite(s))]
    return {"q": q.tolist(), "success": bool(res.success), "found": found,
            "position_error": _finite(float(res.position_error)),
            "orientation_error": _finite(float(res.orientation_error)),
            "message": res.message or "", "method": res.method, "at_limit": at_limit.tolist(),
            "solutions": sols, "T": T_q.tolist(),
            "rpy_xyz": np.concatenate([se3.rpy_from_matrix(T_q[:3, :3]), T_q[:3, 3]]).tolist(),
            "scene": build_scene(robot, q).to_json(), "motions": _motions(robot, q), **_arm_angle(robot, q),
            "collision": _collision(robot, q, collision, text, fmt, base_link, tip_link, tool_row)}


def collision_at(text: str, fmt: str, q: Any, base_link: str | None = None, tip_link: str | None = None,
                 tool_row: bool = False) -> dict[str, Any]:
    """Only the self-collision answer at ``q``: what the page asks again, for the q it shows, while the
    robot's model is being built (nothing else of the page changes).

    The robot is the one ``describe`` reads from text, fmt, base_link, tip_link and tool_row (the same
    memoised robot and model). Returns ``q`` (the (n,) configuration asked about, rad and length units;
    exactly n numbers are required) and ``collision``, as ``describe``'s with ``collision`` true.
    """
    robot, _, _ = _robot(text, fmt, base_link, tip_link, tool_row)
    Q = _q_of(robot, q)
    return {"q": Q.tolist(), "collision": _collision(robot, Q, True, text, fmt, base_link, tip_link, tool_row)}


def _collision(robot: Robot, q: np.ndarray, wanted: bool, text: str, fmt: str, base_link: str | None,
               tip_link: str | None, tool_row: bool) -> dict[str, Any] | None:
    """The self-collision answer at q when ``wanted`` (``collision_api``), keyed as ``_robot`` memoises."""
    if wanted is not True:
        return None
    from .collision_api import collision_answer

    key = (text, fmt or "auto", base_link or None, tip_link or None, tool_row is True)
    return collision_answer(robot, key, text, q)


def _arm_angle(robot: Robot, q: np.ndarray) -> dict[str, Any]:
    """``srs``: the robot is an SRS arm (``kinematics.srs_geometry``); ``arm_angle``: q's (radians; None
    where undefined or not SRS)."""
    from ..kinematics.srs_geometry import arm_angle_of, srs_geometry

    try:
        srs_geometry(robot)
    except InputError:
        return {"srs": False, "arm_angle": None}
    return {"srs": True, "arm_angle": _finite(float(arm_angle_of(robot, q)))}


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


def export(text: str, fmt: str, to: str, base_link: str | None = None, tip_link: str | None = None,
           tool_row: bool = False) -> tuple[str, str, str]:
    """A download of the robot: (file name, MIME type, content).

    ``to`` is one of EXPORTS: the full document as 'yaml' or 'json', 'urdf', or one representation
    as a YAML document holding ``joints`` and that section only.

    ``text``, ``fmt``: the robot, as the page holds it (a robot file's text and its format, 'auto' to guess);
    ``base_link``, ``tip_link``: its chain; ``tool_row``: a table's last row is the tool, not a joint.
    """
    from ..io.documents.reader import document_from_robot, dump

    if to not in EXPORTS:
        raise InputError(f"download: {quote(to)} is not one of {', '.join(EXPORTS)}")
    robot, _, _ = _robot(text, fmt, base_link, tip_link, tool_row)
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
