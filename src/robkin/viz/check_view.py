"""The GUI's visual check: robot B against the robot shown, judged as ``robkin check`` judges it.

The verdict is ``robkin check``'s, from the same library calls: ``equivalence.compare`` for the
kinematics, then ``dynamics.compare.compare_masses`` for the mass properties, and the pair is the same
robot only when both say so (``check`` exits 0). So a copy with one link 0.5 kg heavier is "DIFFER" in
the page as on the command line, with the same first difference. The answer also carries what the
page draws: B's scene at the same q (its differences from A multiplied by ``exaggerate``, see
:mod:`robkin.viz.difference`), the difference arrows, and each body's mass in A and in B side by side.
"""

from __future__ import annotations

import warnings
from typing import Any, Callable

import numpy as np

from ..errors import InputError, quote
from ..robot import Robot

__all__ = ["check_other", "mass_rows"]


def check_other(robot: Robot, Q: np.ndarray, other: Any,
                parse: Callable[[Any, Any, Any, Any, Any], tuple[Robot, list[str], tuple[str, ...]]]
                ) -> dict[str, Any]:
    """Robot B (``other``: text, fmt, base_link, tip_link, tool_row, exaggerate) against ``robot`` at q.

    Parameters
    ----------
    robot : Robot
        Robot A, the one shown.
    Q : (n,) array
        A's joint values; B is drawn at the same q when it has as many joints (else at zero).
    other : dict
        The request's ``other`` field.
    parse : callable
        ``(text, fmt, base_link, tip_link, tool_row) -> (robot, warnings, links)``: the GUI's memoised reader.

    Returns
    -------
    dict
        ``comparison`` (``Comparison.to_dict()``, as ``robkin check --json``), ``mass``
        (``MassComparison.to_dict()``, the ``mass`` object of ``check --json``), ``lines`` (the verdict
        and mass-properties lines ``robkin check`` prints), ``same`` (``check``'s exit status would be
        0), ``first_difference`` (the kinematic one, else the mass one; None when same),
        ``first_joint`` (index of the first joint that is not the same, or None), ``masses`` (see
        :func:`mass_rows`), B's ``scene``, ``arrows`` and the ``exaggerate`` factor.
    """
    from ..dynamics.compare import compare_masses, same_robot
    from ..equivalence.comparison import compare
    from .scene import build_scene

    if not isinstance(other, dict):
        raise InputError("other: expected an object with the second robot's text")
    try:
        b, _, _ = parse(other.get("text"), other.get("fmt"), other.get("base_link"), other.get("tip_link"),
                        other.get("tool_row"))
    except InputError as exc:
        raise InputError(f"robot B: {exc}") from None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # B's conversion notes are not about the robot shown
        result = compare(robot, b)          # what `robkin check A B` calls, with its default tolerance
        masses = compare_masses(robot, b, result)
    same = same_robot(result, masses)  # `robkin check`'s exit status 0
    # the first joint that is not the same: a different axis, or the same axis with another sign or zero
    first = next((m.index for m in result.joints if m.status != "same"), None)
    if first is None and result.n_a != result.n_b:
        first = min(result.n_a, result.n_b)
    first_difference = result.first_difference if not result.same else (
        None if masses.same is not False else masses.first_difference)
    qb = Q if b.n == robot.n else np.zeros(b.n)
    scene_b = build_scene(b, qb, label=b.name or "B")
    factor, arrows = _exaggeration(other.get("exaggerate")), []
    if b.n == robot.n and np.array_equal(b.revolute, robot.revolute):
        from .difference import difference_arrows, exaggerate

        scene_a = build_scene(robot, Q)
        arrows = [a.to_json() for a in difference_arrows(scene_a, scene_b, factor)]
        scene_b = exaggerate(scene_a, scene_b, factor)
    return {"name": b.name or "", "n": b.n, "scene": scene_b.to_json(), "comparison": result.to_dict(),
            "mass": masses.to_dict(), "lines": [f"verdict: {result.verdict()}", masses.summary()],
            "same": same, "first_difference": first_difference, "first_joint": first,
            "masses": mass_rows(robot, b, masses), "exaggerate": factor, "arrows": arrows}


def mass_rows(a: Robot, b: Robot, masses: Any) -> list[dict[str, Any]]:
    """Each body's mass in A and in B, side by side (body 0 is the base; body i moves with joint i).

    ``masses`` is ``compare_masses(a, b, ...)``: where it compared the bodies, each row also has the
    distance between the centres of mass (m), the largest inertia difference (kg m^2) and whether the
    body is the same; elsewhere (a side without inertials, or other mechanisms) those are None and the
    masses are each robot's own (None for a side without inertials or without that body).
    """
    from ..mass_properties import link_masses

    by_index = {body.index: body for body in masses.bodies}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ma, mb = link_masses(a), link_masses(b)
    rows = []
    for i in range(max(a.n, b.n) + 1):
        body = by_index.get(i)
        rows.append({
            "body": i,
            "mass_a": float(ma.mass[i]) if ma is not None and i <= a.n else None,
            "mass_b": float(mb.mass[i]) if mb is not None and i <= b.n else None,
            "name_a": body.name_a if body else "", "name_b": body.name_b if body else "",
            "centre_distance": body.centre_distance if body else None,
            "inertia_difference": body.inertia_difference if body else None,
            "same": body.same if body else None})
    return rows


def _exaggeration(value: Any) -> float:
    """other.exaggerate: the factor differences are drawn with (1 when absent)."""
    from ..io.files.numbers import number

    if value is None:
        return 1.0
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError("other.exaggerate: expected a number from 1 to 1e6")
    k = number(value, "other.exaggerate")
    if not 1 <= k <= 1e6:
        raise InputError(f"other.exaggerate: expected a number from 1 to 1e6, got {quote(value)}")
    return k
