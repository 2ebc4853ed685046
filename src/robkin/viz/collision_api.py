"""The GUI's self-collision answer: which links of the robot shown collide with each other at q.

The page asks with every configuration it shows (``describe`` and ``solve_ik`` with ``collision``
true), so the check rides on the request a slider or a drag already makes. The robot's
self-collision model (``robkin.self_collision.self_collision_model``: capsules, convex parts and the
allowed-collision matrix sampled at 20000 configurations) takes a few seconds to build, so it is
built once per robot in a background thread; until it is ready the answer says ``building`` and the
page asks again. Then each check costs tens of microseconds: the capsule distance of every checked
link pair (compiled), and, for the pairs whose capsules meet, the convex parts of that pair alone
(``level='parts'``: compiled and conservative, the level collision-aware IK uses; a pair called
free is free for the meshes, one called colliding may be a near miss of a few millimetres).

Which files: the robot given on the command line has its collision meshes found as its visuals are
(its file and ``--package-path``, registered by ``make_server``); a robot pasted or loaded in the page
has only its primitive collision shapes (boxes, spheres, cylinders, capsules): the server never opens
a path named by a request, so a pasted robot with collision meshes is answered ``none`` with the
reason, as is a robot without collision geometry.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from ..robot import Robot
    from ..self_collision import SelfCollisionModel

__all__ = ["LEVEL", "register_source", "collision_answer", "stick_segments"]

#: The level of ``SelfCollisionModel.collides`` the GUI answers with (see the module doc).
LEVEL = "parts"
#: What identifies a robot of the page: its request fields (text, format, base link, tip link, tool row).
Key = tuple[str, str, str | None, str | None, bool]
#: Models kept (one per robot text and chain): a few robots switched between.
_KEEP = 4

#: robot text -> (its file, package folders): the command-line robot, whose meshes may be read
_SOURCES: dict[str, tuple[Path, Mapping[str, Path] | None]] = {}
_lock = threading.Lock()
#: one model built at a time: typing in a robot with collision shapes asks for one per edit
_building = threading.Lock()


class _Build:
    """One model being built (in a daemon thread) or built: ``model``, or ``error`` (one line)."""

    def __init__(self, key: Key, robot: Robot, source: Path | None, package_paths: Mapping[str, Path] | None
                 ) -> None:
        self.key = key
        self.done = threading.Event()
        self.model: SelfCollisionModel | None = None
        self.error: str | None = None
        self.superseded = False  # not built: another robot was asked for first (asked again, built anew)
        self.pair_models: dict[tuple[str, str], SelfCollisionModel] = {}
        threading.Thread(target=self._run, args=(robot, source, package_paths), name="robkin-gui-collision",
                         daemon=True).start()

    def _run(self, robot: Robot, source: Path | None, package_paths: Mapping[str, Path] | None) -> None:
        with _building:
            with _lock:  # a robot asked for since then goes first: this one is built when asked again
                stale = next(reversed(_BUILDS), None) != self.key
                if stale:
                    _BUILDS.pop(self.key, None)
            if stale:
                self.superseded = True
                self.done.set()
                return
            self._build(robot, source, package_paths)

    def _build(self, robot: Robot, source: Path | None, package_paths: Mapping[str, Path] | None) -> None:
        from ..self_collision import self_collision_model

        try:
            model = self_collision_model(robot, source, package_paths=package_paths)
            for pair in model.pairs:  # a few ms each: here, not in the middle of a drag
                self.pair_model(model, pair)
            self.model = model
        except InputError as exc:
            self.error = str(exc)
        except Exception as exc:  # noqa: BLE001 - a bug: say so in the page rather than hang on "building"
            self.error = f"internal error ({type(exc).__name__}: {exc}); please report it"
        finally:
            self.done.set()

    def pair_model(self, model: SelfCollisionModel, pair: tuple[str, str]) -> SelfCollisionModel:
        """The model checking only ``pair`` (the others disabled), to name the colliding pairs at the
        parts level, which ``collides`` answers per configuration only."""
        from ..self_collision import DisabledPair

        if pair not in self.pair_models:
            others = [DisabledPair(a, b, "Never") for a, b in model.pairs if (a, b) != pair]
            self.pair_models[pair] = model.with_disabled([*model.disabled, *others])
        return self.pair_models[pair]


_BUILDS: "OrderedDict[Key, _Build]" = OrderedDict()


def register_source(text: str, source: str | Path, package_paths: Mapping[str, Path] | None = None) -> None:
    """Let the robot ``text`` (the one given on the command line) have its collision meshes read from
    ``source``'s folder and ``package_paths``."""
    _SOURCES[text] = (Path(source), package_paths)


def _build(key: Key, robot: Robot, text: str) -> _Build:
    with _lock:
        build = _BUILDS.get(key)
        if build is None:
            source, packages = _SOURCES.get(text, (None, None))
            build = _BUILDS[key] = _Build(key, robot, source, packages)
            while len(_BUILDS) > _KEEP:
                _BUILDS.popitem(last=False)
        _BUILDS.move_to_end(key)
        return build


def stick_segments(robot: Robot, bodies: set[int]) -> list[int]:
    """Indices of the stick figure's segments (``robkin.viz.scene.build_scene``'s ``links`` polyline:
    base, per joint its slide start if prismatic and its origin, then the tool) that move with one of
    ``bodies`` (0: base, k: moves with joint k). A prismatic joint's slide counts as its own body's."""
    owner = [0] if robot.n == 0 else []
    for k in range(1, robot.n + 1):
        owner += [k - 1, k] if not robot.revolute[k - 1] else [k - 1]
    if robot.n:
        owner.append(robot.n)
    return [i for i, b in enumerate(owner) if b in bodies]


def collision_answer(robot: Robot, key: Key, text: str, q: np.ndarray, wait: float = 0.0) -> dict[str, Any]:
    """Which links collide at ``q``, for the page.

    Parameters
    ----------
    robot : Robot
        The robot shown (``gui_api._robot``'s, memoised with its ``key``).
    key : tuple
        What identifies it: its request fields (text, fmt, base link, tip link, tool row).
    text : str
        Its text (the command-line robot's has its mesh files, see ``register_source``).
    q : (n,) array
        The configuration shown (rad, length units).
    wait : float
        Seconds to wait for a model still being built (0: answer ``building`` at once).

    Returns
    -------
    dict
        ``state``: 'building', 'none' (no model: ``message`` says why) or 'ready'; when ready,
        ``collides`` (bool), ``pairs`` ([[link1, link2]] colliding at the parts level), ``links``
        (their links), ``segments`` (stick segments to draw red, see ``stick_segments``), and ``level``.
    """
    build = _build(key, robot, text)
    ready = build.done.wait(wait) if wait > 0 else build.done.is_set()
    if ready and build.superseded:
        build = _build(key, robot, text)
        ready = build.done.wait(wait) if wait > 0 else build.done.is_set()
    if not ready:
        return {"state": "building", "level": LEVEL}
    if build.model is None:
        return {"state": "none", "message": build.error or "no self-collision model", "level": LEVEL}
    model = build.model
    d = model.distances(q)
    touching = [pair for pair, dist in zip(model.pairs, d) if dist <= 0.0]  # capsules meet: ask the parts
    pairs = [list(p) for p in touching if build.pair_model(model, p).collides(q, level=LEVEL)]
    links = sorted({name for p in pairs for name in p}, key=model.links.index)
    body = {c.link: c.body for c in model.capsules}
    return {"state": "ready", "level": LEVEL, "collides": bool(pairs), "pairs": pairs, "links": links,
            "segments": stick_segments(robot, {body[name] for name in links})}
