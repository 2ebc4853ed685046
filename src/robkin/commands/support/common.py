"""Argument helpers shared by the commands: input loading, joint vectors, poses, output files."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from ...errors import InputError
from ...io.files.numbers import number_list

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np

    from ...robot import Robot

__all__ = ["add_input", "add_allow_xacro", "add_from", "add_package_path", "package_paths", "load_input", "seed",
           "parse_q", "parse_pose", "number_option_fix"]

def add_input(p: argparse.ArgumentParser, many: bool = False) -> None:
    """INPUT argument(s) plus the URDF chain selectors."""
    p.add_argument("input", nargs="+" if many else None, metavar="INPUT",
                   help="robot document (.yaml/.yml/.json), URDF (.urdf; .xacro with --allow-xacro), "
                        "MJCF (.xml/.mjcf), SDF (.sdf), USD (.usda/.usd/.usdc) or table (.csv/.tsv/.txt, see --from)"
                        + (" (one or more)" if many else ""))
    p.add_argument("--base-link", metavar="LINK", help="URDF/SDF link or MJCF body/site: first of the serial chain")
    p.add_argument("--tip-link", metavar="LINK", help="URDF/SDF link or MJCF body/site: last of the chain (the tool)")
    add_allow_xacro(p)
    add_from(p)


def add_from(p: argparse.ArgumentParser) -> None:
    """--from: which table a table file (.csv/.tsv/.txt) holds, where the file does not say (any
    registered representation with a table form; the registry imports nothing heavy)."""
    from ...representations.registry import names

    table_inputs = names("csv")
    p.add_argument("--from", dest="representation", choices=table_inputs, metavar="TABLE",
                   help="for a table file (.csv/.tsv/.txt) that does not say what it holds: "
                        + ", ".join(table_inputs) + ". A CSV written by 'robkin convert --format csv' says it "
                        "(except a PoE's frame); bare rows 'a d alpha theta [R|P]' need --from dh or mdh")


def add_allow_xacro(p: argparse.ArgumentParser) -> None:
    """The opt-in to expand .xacro input (xacro runs code from the file, so it is off by default)."""
    p.add_argument("--allow-xacro", action="store_true",
                   help="expand .xacro input with the xacro package. A .xacro file is a program: it can run "
                        "code and read files and environment variables, so use this only for files you trust "
                        "(or expand it yourself: xacro FILE.xacro > FILE.urdf)")


def add_package_path(p: argparse.ArgumentParser) -> None:
    """The repeatable ``--package-path NAME=DIR`` that tells where mesh files' packages are."""
    p.add_argument("--package-path", metavar="NAME=DIR", action="append", default=[], type=_package_path,
                   help="where package://NAME/... (or SDF model://NAME/...) mesh files are: the folder of package "
                        "NAME (repeatable; tried before the folders above the robot file, ROS_PACKAGE_PATH, "
                        "AMENT_PREFIX_PATH and GAZEBO_MODEL_PATH)")


def _package_path(text: str) -> tuple[str, Path]:
    from ...io.meshes.files import parse_package_path

    try:
        return parse_package_path(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def package_paths(args: argparse.Namespace) -> dict[str, Path]:
    """NAME -> folder of the command's ``--package-path`` options (the last one given for a NAME wins)."""
    return dict(getattr(args, "package_path", None) or [])


def load_input(path: str, args: argparse.Namespace) -> "Robot":
    """The robot in ``path``, with the command's chain selectors and --allow-xacro."""
    from ...io import load

    return load(path, base_link=getattr(args, "base_link", None), tip_link=getattr(args, "tip_link", None),
                allow_xacro=getattr(args, "allow_xacro", False),
                representation=_table_only(path, getattr(args, "representation", None), args))


def _table_only(path: str, representation: str | None, args: argparse.Namespace) -> str | None:
    """--from for a table file; for other files only when it is the one input (so that the loader
    says it does not apply), not when a command takes several inputs of mixed kinds."""
    if representation is None or path.lower().endswith((".csv", ".tsv", ".txt")):
        return representation
    return representation if not isinstance(getattr(args, "input", None), list) else None


def seed(text: str) -> int:
    """argparse type of a random seed: a whole number 0 .. 2**63 - 1 (what numpy's generators accept)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text[:40]}' is not a whole number") from None
    if not 0 <= value < 2 ** 63:
        raise argparse.ArgumentTypeError(f"{value} is not a seed (0 .. 2**63 - 1)")
    return value


def add_threads(p: argparse.ArgumentParser) -> None:
    """--threads N: how many threads this command's batch kernels may use (robkin.set_threads)."""
    p.add_argument("--threads", type=positive_int, metavar="N",
                   help="threads for the batch kernels (default: ROBKIN_NUM_THREADS, else OMP_NUM_THREADS, else "
                        "every core this process may use); the results are the same bits on any number of "
                        "threads")


def positive_int(text: str) -> int:
    """argparse type of a count (--threads, --samples, --plan, ...): a whole number >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text[:40]}' is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value}: expected a whole number >= 1")
    return value


def parse_q(text: str, n: int, option: str = "--q") -> "np.ndarray":
    """Joint values 'q1,q2,...' (numbers or expressions like pi/2) for a robot with n joints."""
    import numpy as np

    values = number_list(text, option)
    if len(values) != n:
        raise InputError(f"{option}: the robot has {n} joints, got {len(values)} values")
    return np.array(values)


def parse_pose(text: str, option: str = "--pose", degrees: bool = False) -> "np.ndarray":
    """A pose from 'x,y,z,roll,pitch,yaw' (URDF rpy, radians, or degrees if asked) or 16 numbers
    (row-major 4x4)."""
    import numpy as np

    from ... import se3
    from ...robot import check_pose

    values = number_list(text, option)
    if len(values) == 6:
        rpy = np.radians(values[3:]) if degrees else values[3:]
        T = se3.homogeneous(se3.matrix_from_rpy(rpy), values[:3])
    elif len(values) == 16:
        T = np.array(values).reshape(4, 4)
    else:
        raise InputError(f"{option}: expected 6 numbers x,y,z,roll,pitch,yaw or 16 numbers (row-major 4x4), "
                         f"got {len(values)}")
    return check_pose(T, option)


def add_degrees(p: argparse.ArgumentParser, what: str) -> None:
    """The --degrees switch of commands that read or print angles."""
    p.add_argument("--degrees", action="store_true", help=f"angles in degrees: {what}")


def revolute_degrees(robot: Robot, q: np.ndarray, to_radians: bool) -> np.ndarray:
    """q (..., n) with the revolute joints' values converted degrees -> radians (or back)."""
    import numpy as np

    return np.where(robot.revolute, np.radians(q) if to_radians else np.degrees(q), q)


def number_option_fix(argv: list[str], options: tuple[str, ...]) -> list[str]:
    """Join '--q -0.5,1' into '--q=-0.5,1' so that argparse does not take '-0.5,1' for an option."""
    out: list[str] = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in options and i + 1 < len(argv) and _looks_numeric(argv[i + 1]):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def _looks_numeric(s: str) -> bool:
    return len(s) > 1 and s[0] == "-" and (s[1].isdigit() or s[1] == "." or s[1:3].lower() == "pi")
