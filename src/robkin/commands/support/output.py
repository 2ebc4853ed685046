"""Output conventions shared by the commands: JSON on stdout, "wrote PATH" and warnings on stderr.

- ``print_json``: every ``--json`` output, in the one style of ``robkin.io.files.jsontext``.
- ``wrote``: one line ``wrote PATH`` on stderr for every file written, so that a run that writes
  says where, while stdout stays clean for the data.
- ``warn_outside_limits``: one warning line per joint whose value lies outside its limits.
"""

from __future__ import annotations

import sys
from os import PathLike
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np

    from ...robot import Robot

__all__ = ["print_json", "wrote", "warn_outside_limits", "joint_names"]


def print_json(obj: Any) -> None:
    """Print ``obj`` as JSON in robkin's style (indented, full precision) to stdout."""
    from ...io.files.jsontext import dumps

    print(dumps(obj))


def wrote(path: str | PathLike[str]) -> None:
    """Tell the user (stderr) that a file was written."""
    print(f"wrote {path}", file=sys.stderr)


def joint_names(robot: "Robot") -> list[str]:
    """The joint names in order, the key to every joint vector in a JSON output."""
    return [j.name for j in robot.joints]


def warn_outside_limits(robot: "Robot", q: "np.ndarray", option: str = "--q") -> None:
    """Print one warning per joint of ``q`` (n,) outside its limits (stderr), naming the joint.

    The comparison is exact: a value typed with the limits' own digits is at the limit, not outside.
    """
    from ...io.tables.terminal import fmt_num

    for joint, value in zip(robot.joints, q):
        unit = "rad" if joint.revolute else "m"
        lower = -float("inf") if joint.lower is None else joint.lower
        upper = float("inf") if joint.upper is None else joint.upper
        if not lower <= value <= upper:
            print(f"robkin: warning: {option}: joint '{joint.name}' = {fmt_num(value)} {unit} is outside its limits "
                  f"[{fmt_num(lower)}, {fmt_num(upper)}] {unit}", file=sys.stderr)
