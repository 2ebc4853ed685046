"""``robkin convert --to urdf|mjcf`` reads what it wrote and checks it against the robot it came from.

The written file is loaded again by robkin's own reader (the same chain: base and tip link), compared
kinematically (``robkin.equivalence.comparison``: FK at well-spread configurations) and by mass
properties (``robkin.dynamics.compare.compare_masses``: per body mass, centre and inertia, and M(q),
g(q) at 16 configurations), and one line on stderr says the outcome: what could not be checked (a
robot without inertials), or where the written file differs (a warning; the file is kept, since the
differences the writer makes on purpose, such as a placeholder mass MuJoCo needs, were warned about
already).

An MJCF is then simulated (``sim_line``, ``robkin.simulation.mujoco_check.hold_check``): MuJoCo loads it
without warnings, ``home`` is inside the limits, the self-contacts at home are counted, and 5 s from
``home`` under its actuators hold it: one more line with the numbers (when it does not hold and there
are self-contacts at home, simulated again with contacts off to say whether they are the cause), or,
when MuJoCo is not installed, one saying the simulation was not checked.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["check_written", "sim_line"]


def _ends(robot: Robot) -> tuple[str | None, str | None]:
    """The chain's base and tip link in the written file (None: the reader's default, for a plain
    chain written without link names)."""
    b = robot.bodies
    if b.links and len(b.chain) == robot.n + 1 and b.tip:
        return b.chain[0], b.tip
    return None, None


def check_written(robot: Robot, path: Path, fmt: str) -> str:
    """Read ``path`` (a URDF or MJCF robkin wrote for ``robot``) back and compare; returns the line
    printed on stderr (``robkin: note: ...`` or ``robkin: warning: ...``)."""
    from ...dynamics.compare import compare_masses
    from ...equivalence.comparison import compare
    from ...io import load

    base, tip = _ends(robot)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the reader's notes (held joints, ...) were said for the source
        try:
            back = load(path, base_link=base, tip_link=tip)
        except Exception as exc:  # noqa: BLE001 - a writer bug must not hide the written file
            line = f"robkin: warning: {path}: could not be read back to check it ({exc})"
            print(line, file=sys.stderr)
            return line
    kin = compare(robot, back)
    masses = compare_masses(robot, back, kin)
    if not kin.same:
        line = f"robkin: warning: {path}: read back, its kinematics differ from the source's ({kin.verdict()})"
    elif not masses.checked:
        reason = "the robot has no inertials" if not robot.bodies.inertials else masses.reason
        line = f"robkin: note: {path}: FK checked; mass properties not checked ({reason})"
    elif masses.same:
        line = (f"robkin: note: {path}: read back: FK and mass properties equal the source's ({len(masses.bodies)} "
                f"bodies, {masses.total_mass_b:.6g} kg; M(q), g(q) within {max(masses.mass_matrix_error, masses.gravity_error):.1g})")
    else:
        from ...io.mjcf.writer import CHANGED_MARK

        why = ""
        if fmt == "mjcf" and CHANGED_MARK in Path(path).read_text(errors="replace")[:4096]:
            why = " (the writer changed masses MuJoCo refuses, as warned above)"
        line = f"robkin: warning: {path}: read back, its mass properties differ{why}: {masses.first_difference}"
    print(line, file=sys.stderr)
    if fmt == "mjcf":
        print(sim_line(path), file=sys.stderr)
    return line


def sim_line(path: Path) -> str:
    """The simulation check's line (``robkin: note: ...`` when home holds, else ``robkin: warning: ...``)."""
    from ...simulation.mujoco_check import available, hold_check

    if not available():
        return f"robkin: note: {path}: simulation not checked (MuJoCo is not installed: pip install mujoco)"
    try:
        report = hold_check(path)
    except Exception as exc:  # noqa: BLE001 - a writer bug must not hide the written file
        return f"robkin: warning: {path}: MuJoCo could not simulate it ({str(exc).splitlines()[0] if str(exc) else exc!r})"
    why = ""
    if not report.holds and report.contacts and not report.warnings:  # the servos, or the contacts?
        free = hold_check(path, contacts=False)
        if free.holds:
            why = (f"; with contacts off it holds (max drift {free.drift:.1e}): the self-contacts at home "
                   f"kick it")
        report.wall += free.wall
    kind = "note" if report.holds else "warning"
    return f"robkin: {kind}: {path}: MuJoCo: {report.line()}{why} ({report.wall:.2g} s)"
