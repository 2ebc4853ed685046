"""``self_collision_model``: a robot's self-collision model (capsules and allowed-collision matrix) in one
call, and the model ``Robot.self_collision`` uses (the last one built for that robot object)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Mapping

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from ..robot import Robot
    from .model import DisabledPair, SelfCollisionModel

__all__ = ["self_collision_model", "model_of", "self_collision", "self_collision_distances", "DEFAULT_SAMPLES"]

#: Configurations the allowed-collision matrix is sampled at (MoveIt's Setup Assistant: 10000 by default;
#: twice that leaves fewer rarely colliding pairs taken for "Never").
DEFAULT_SAMPLES = 20000

#: the attribute of a Robot object that keeps the model last built for it: on the robot itself, so the
#: model goes with it (a WeakKeyDictionary would never free it: the model refers to its robot)
_KEPT = "_self_collision_model"


def self_collision_model(robot: Robot, source: str | Path | None = None, *,
                         package_paths: Mapping[str, Path] | None = None, samples: int = DEFAULT_SAMPLES,
                         rng: np.random.Generator | int | None = 0, exact: bool | None = None,
                         disabled: list[DisabledPair] | None = None) -> SelfCollisionModel:
    """The self-collision model of ``robot``: a conservative capsule per link with collision geometry
    (``capsules``) and the allowed-collision matrix (``acm``), kept as the model ``Robot.self_collision``
    and ``Robot.ik(avoid_self_collision=True)`` use for this robot object.

    Parameters
    ----------
    robot : Robot
        With collision shapes (``robot.bodies``), as read from a URDF, MJCF or SDF.
    source : path, optional
        The robot file its collision mesh names are relative to (needed for meshes).
    package_paths : mapping NAME -> folder, optional
        Folders of ``package://NAME`` meshes.
    samples : int
        Configurations the allowed-collision matrix is sampled at (``acm``).
    rng : Generator, int seed or None
        The samples' source; the default seed 0 makes the matrix reproducible.
    exact : bool, optional
        Judge the pairs whose capsules meet with the exact meshes (coal); None: when coal is installed.
    disabled : list of DisabledPair, optional
        A given allowed-collision matrix (an SRDF read with ``robkin.io.srdf.read_srdf``) instead of
        sampling one.
    """
    from .acm import allowed_collisions
    from .capsules import link_capsules, link_parts
    from .exact import ExactChecker, exact_available
    from .geometry import link_geometry
    from .model import SelfCollisionModel

    if not isinstance(samples, (int, np.integer)) or isinstance(samples, bool) or samples < 1:
        raise InputError(f"samples: expected a positive integer, got {samples!r}")
    links = link_geometry(robot, source, package_paths)
    if len(links) < 2:
        raise InputError(f"robot {robot.name or ''}: {len(links)} link(s) with collision geometry; "
                         "self-collision needs at least two")
    use_exact = exact_available() if exact is None else bool(exact)
    checker = ExactChecker(robot, links) if use_exact else None
    model = SelfCollisionModel(robot, link_capsules(links), exact=checker, parts=link_parts(links))
    if disabled is not None:
        model = model.with_disabled(disabled)
    else:
        model = SelfCollisionModel(robot, model.capsules, allowed_collisions(model, checker, int(samples), rng),
                                   int(samples), checker, model.parts)
    robot.__dict__[_KEPT] = model
    return model


def model_of(robot: Robot) -> SelfCollisionModel:
    """The model last built for this robot object, else one built now from its collision shapes (which
    needs them to be primitives or meshes found without the robot file: else build it with
    ``self_collision_model(robot, source)``)."""
    model = robot.__dict__.get(_KEPT)
    if model is None:
        model = self_collision_model(robot)
    return model


def self_collision(robot: Robot, q: ArrayLike, *, level: str = "capsules", model: SelfCollisionModel | None = None,
                   threads: int | None = None) -> bool | np.ndarray:
    """Whether the robot collides with itself at q: (n,) -> bool, (N, n) -> (N,) bool array.

    ``level='capsules'`` (default): capsules around the links, compiled, every core; conservative: False
    means free for the links' collision geometry, True may be a near miss. ``'parts'``: what the capsules
    flag is tested again with the links' convex parts (compiled; still conservative, tighter).
    ``'exact'``: then with the meshes (coal), so True is a real contact (``SelfCollisionModel.collides``).

    Parameters
    ----------
    robot : Robot
        The robot (its model: ``model``, else the last one built for it, ``model_of``).
    q : array (n,) or (N, n)
        Joint values (rad / length units).
    level : {'capsules', 'parts', 'exact'}
        How far the check goes (above).
    model : SelfCollisionModel, optional
        Default ``model_of(robot)``.
    threads : int, optional
        Threads of the compiled kernels (None or 0: automatic, ``robkin.threads``).
    """
    return (model or model_of(robot)).collides(q, level=level, threads=threads)


def self_collision_distances(robot: Robot, q: ArrayLike, *, model: SelfCollisionModel | None = None,
                             threads: int | None = None) -> np.ndarray:
    """Distance between the capsules of each checked link pair (length units, negative: overlap): q (n,)
    -> (P,), (N, n) -> (N, P), pairs in the order of ``model.pairs`` (``SelfCollisionModel.closest`` names
    the nearest ones).

    Parameters
    ----------
    robot : Robot
        The robot.
    q : array (n,) or (N, n)
        Joint values (rad / length units).
    model : SelfCollisionModel, optional
        Default ``model_of(robot)``.
    threads : int, optional
        Threads of the compiled kernel (None or 0: automatic, ``robkin.threads``).
    """
    return (model or model_of(robot)).distances(q, threads=threads)
