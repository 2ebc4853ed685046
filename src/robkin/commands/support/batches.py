"""``robkin fk --q-file`` and ``robkin ik --poses``: many joint vectors or poses in one run.

The rows go through the library's batch kernels (``Robot.fk`` on (N, n), ``Robot.ik`` on (N, 4, 4)),
in blocks of ``BLOCK`` so that a long run can show its progress; the results are the same as one
call with the whole array for FK and for the closed-form IK, and for numeric IK those of calls on
blocks of ``BLOCK`` targets with one random generator seeded by --seed.

Files: see ``robkin.io.batch_files``. Columns are found by name: joint values by the joints' names
(as ``ik -o out.csv`` writes them) or q1..qn; poses by ``x, y, z`` and ``qw, qx, qy, qz`` (as ``fk -o
out.csv`` writes them) or ``roll, pitch, yaw``, or ``m11 .. m34`` / ``m11 .. m44``; a file without a
header has n values (joints) or 6 (x, y, z, roll, pitch, yaw), 7 (x, y, z, qw, qx, qy, qz), 12 or 16
(the matrix row by row) values per row.
"""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING, Any, Callable, Iterator

import numpy as np

from ...errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from ...io.batch_files import Rows
    from ...robot import Robot

__all__ = ["BLOCK", "PROGRESS_FROM", "add_output", "fk_batch", "ik_batch", "closest_of", "q_rows", "pose_rows"]

#: Targets per call of the batch kernels: small enough for progress every ~0.1 s of numeric IK,
#: large enough that the per-call overhead (~50 us) is lost in the work.
BLOCK = 1024
#: Progress is shown (on stderr, when it is a terminal) for runs of at least this many rows: a
#: shorter run ends before a progress line would help.
PROGRESS_FROM = 4 * BLOCK
_M12 = [f"m{r}{c}" for r in (1, 2, 3) for c in (1, 2, 3, 4)]
_M16 = _M12 + ["m41", "m42", "m43", "m44"]


def add_output(p: argparse.ArgumentParser, what: str) -> None:
    p.add_argument("-o", "--output", metavar="OUT",
                   help=f"with {what}: write the results to OUT.csv (a header, one row per input row, with "
                        "success and error columns), OUT.npy (one array), OUT.npz (every column) or "
                        "OUT.json; without -o, CSV (or --json) on stdout")


def _check_output(args: argparse.Namespace) -> None:
    """Refuse an -o name without a known extension before any work is done."""
    import os

    if args.output and os.path.splitext(args.output)[1].lower() not in (".csv", ".npy", ".npz", ".json"):
        raise InputError(f"{args.output}: -o writes .csv, .npy, .npz or .json; name the output accordingly")


def _columns(rows: "Rows", names: list[str]) -> np.ndarray | None:
    """The columns called ``names`` (case-insensitive), in that order, or None if one is missing."""
    if rows.columns is None:
        return None
    at = {c.strip().lower(): i for i, c in enumerate(rows.columns)}
    idx = [at.get(n.lower()) for n in names]
    return None if None in idx else rows.take(idx)  # type: ignore[arg-type]


def q_rows(rows: "Rows", robot: "Robot") -> np.ndarray:
    """Joint vectors (N, n) from a batch file: by joint name, q1..qn, or n values per row."""
    n = robot.n
    names = [j.name for j in robot.joints]
    Q = _columns(rows, names)
    if Q is None:
        Q = _columns(rows, [f"q{i + 1}" for i in range(n)])
    if Q is None:
        if rows.columns is not None:
            raise InputError(f"{rows.source}: the header names no joint columns; expected the joint names "
                             f"({', '.join(names)[:80]}) or q1..q{n}")
        if rows.values.shape[1] != n:  # (without a header every column is data: no text columns)
            raise InputError(f"{rows.source}: {rows.values.shape[1]} values per row; the robot has {n} joints "
                             f"(shape {rows.shape})")
        Q = rows.values
    _finite(Q, rows.source, "joint value")
    return np.ascontiguousarray(Q, dtype=float)


def pose_rows(rows: "Rows", degrees: bool = False) -> np.ndarray:
    """Target poses (N, 4, 4) from a batch file (see the module), each checked as a rigid pose."""
    from ... import se3
    from ...robot import check_pose

    V = rows.values
    p = _columns(rows, ["x", "y", "z"])
    quat, rpy, m12, m16 = (_columns(rows, ["qw", "qx", "qy", "qz"]), _columns(rows, ["roll", "pitch", "yaw"]),
                           _columns(rows, _M12), _columns(rows, _M16))
    if rows.columns is None:
        width = V.shape[1]
        if rows.shape[1:] == (4, 4) or width == 16:
            m16 = V
        elif width == 12:
            m12 = V
        elif width == 7:
            p, quat = V[:, :3], V[:, 3:]
        elif width == 6:
            p, rpy = V[:, :3], V[:, 3:]
        else:
            raise InputError(f"{rows.source}: {width} values per row; a pose is 6 (x, y, z, roll, pitch, yaw), "
                             f"7 (x, y, z, qw, qx, qy, qz), 12 or 16 (the 4x4 matrix row by row) values")
    N = len(V)
    T = np.broadcast_to(np.eye(4), (N, 4, 4)).copy()
    if m16 is not None:
        T = m16.reshape(N, 4, 4).copy()
    elif m12 is not None:
        T[:, :3] = m12.reshape(N, 3, 4)
    elif p is not None and (quat is not None or rpy is not None):
        T[:, :3, 3] = p
        if quat is not None:  # the quaternion is the rotation when both are there (no gimbal lock)
            from ...io.mjcf.format import matrix_from_quat

            _finite(quat, rows.source, "quaternion value")
            norms = np.linalg.norm(quat, axis=1)
            if np.any(np.abs(norms - 1) > 1e-6):  # 1e-6: quaternions written with ~7 digits are unit to that
                k = int(np.flatnonzero(np.abs(norms - 1) > 1e-6)[0])
                raise InputError(f"{rows.source}: row {k + 1}: quaternion (qw, qx, qy, qz) has norm "
                                 f"{norms[k]:.6g}; expected a unit quaternion")
            T[:, :3, :3] = np.moveaxis(matrix_from_quat((quat / norms[:, None]).T), -1, 0)
        else:
            _finite(rpy, rows.source, "roll/pitch/yaw value")
            T[:, :3, :3] = se3.matrix_from_rpy(np.radians(rpy) if degrees else rpy)
    else:
        raise InputError(f"{rows.source}: the header names no pose columns; expected x, y, z with qw, qx, qy, qz "
                         f"or roll, pitch, yaw, or m11 .. m34 (or m11 .. m44)")
    _finite(T, rows.source, "pose value")
    for k in range(N):  # the same check (and projection of 3-decimal rotations) as --pose
        T[k] = check_pose(T[k], f"{rows.source}: row {k + 1}")
    return T


def _finite(values: np.ndarray, source: str, what: str) -> None:
    bad = np.argwhere(~np.isfinite(values))
    if bad.size:
        raise InputError(f"{source}: row {bad[0][0] + 1}: {what} {values[tuple(bad[0])]} is not a finite number")


def _blocks(N: int, label: str, step: Callable[[slice], None]) -> None:
    """Call ``step`` on consecutive blocks of BLOCK rows; a progress line on a terminal's stderr for
    runs of at least PROGRESS_FROM rows."""
    show = N >= PROGRESS_FROM and _is_terminal(sys.stderr)
    for start in range(0, N, BLOCK):
        step(slice(start, min(N, start + BLOCK)))
        if show:
            done = min(N, start + BLOCK)
            print(f"\r{label}: {done}/{N} ({100 * done // N}%)", end="", file=sys.stderr, flush=True)
    if show:
        print(file=sys.stderr)


def _is_terminal(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


def _emit(args: argparse.Namespace, columns: list[str], table: Any, arrays: dict[str, Any],
          main_array: str, document: Any) -> None:
    """Results to -o (by extension) or stdout (CSV, or JSON with --json). ``table`` (rows) and
    ``document`` may be functions giving them: only the one the output needs is made."""
    from ...io.batch_files import write_csv, write_rows
    from .output import print_json, wrote

    if args.output:
        write_rows(args.output, columns, table, arrays, main_array, document)
        wrote(args.output)
    elif args.json:
        print_json(document() if callable(document) else document)
    else:
        write_csv(sys.stdout, columns, table() if callable(table) else table)


def _json_rows(args: argparse.Namespace, N: int, source: str) -> None:
    """Refuse JSON output of more than MAX_JSON_ROWS rows before any work (its rows are Python dicts)."""
    from ...io.batch_files import MAX_JSON_ROWS

    if N > MAX_JSON_ROWS and (args.json or (args.output or "").lower().endswith(".json")):
        raise InputError(f"{source}: {N} rows; JSON output (--json, -o .json) holds at most {MAX_JSON_ROWS} rows: "
                         f"write .npy, .npz or .csv")


def fk_batch(robot: "Robot", args: argparse.Namespace) -> int:
    """``robkin fk --q-file FILE``: the tool pose at every joint vector of the file."""
    from ... import se3
    from ...io.batch_files import read_rows
    from .common import revolute_degrees

    _check_output(args)
    Q = q_rows(read_rows(args.q_file, key="q"), robot)
    _json_rows(args, len(Q), "standard input" if args.q_file == "-" else args.q_file)
    if args.degrees:
        Q = revolute_degrees(robot, Q, to_radians=True)
    N = len(Q)
    T = np.empty((N, 4, 4))

    def step(s: slice) -> None:
        T[s] = robot.fk(Q[s])

    _blocks(N, "fk", step)
    rpy = se3.rpy_from_matrix(T[:, :3, :3])
    quat = se3.quaternion_from_matrix(T[:, :3, :3])
    lim = robot.limits
    outside = (Q < lim[:, 0]) | (Q > lim[:, 1])
    names = [j.name for j in robot.joints]
    rows_out = np.flatnonzero(outside.any(axis=1))  # notes only for these: no Python string per row
    notes = {int(k): ", ".join(f"{names[i]} outside its limits" for i in np.flatnonzero(outside[k])) for k in rows_out}
    if len(rows_out):
        print(f"robkin: warning: {len(rows_out)} of {N} rows have joint values outside the limits "
              f"(see the 'error' column)", file=sys.stderr)
    if args.degrees:
        rpy = np.degrees(rpy)
    q_out = revolute_degrees(robot, Q, to_radians=False) if args.degrees else Q
    columns = ["row", *names, "x", "y", "z", "roll", "pitch", "yaw", "qw", "qx", "qy", "qz", "success", "error"]

    def table() -> Iterator[list[Any]]:  # CSV only, one row at a time
        for k in range(N):
            yield [k + 1, *q_out[k], *T[k, :3, 3], *rpy[k], *quat[k], True, notes.get(k, "")]

    def document() -> dict[str, Any]:  # JSON only (at most MAX_JSON_ROWS rows)
        return {"joints": names, "results": [{"q": q_out[k], "T": T[k], "position": T[k, :3, 3], "rpy": rpy[k],
                                              "quaternion": dict(zip("wxyz", quat[k])), "success": True,
                                              "error": notes.get(k) or None} for k in range(N)]}

    _emit(args, columns, table, {"T": T, "q": q_out, "position": T[:, :3, 3], "rpy": rpy, "quaternion": quat},
          "T", document)
    return 0


def ik_batch(robot: "Robot", args: argparse.Namespace, solve: dict[str, Any]) -> int:
    """``robkin ik --poses FILE``: one solution (nearest to --q0) per target pose of the file.

    A target without a solution is not an error: its row has success false, the reason, and the
    closest configuration found with its distance (position, orientation) from the target.

    The results are arrays (q, success, errors; a code per target into the distinct reasons; with --all
    the solutions stacked with a count per target); the CSV rows and the JSON document are made from
    them only for the output that needs them, CSV rows one at a time.
    """
    from ...io.batch_files import read_rows
    from .common import revolute_degrees

    _check_output(args)
    targets = pose_rows(read_rows(args.poses, key="poses"), degrees=args.degrees)
    _json_rows(args, len(targets), "standard input" if args.poses == "-" else args.poses)
    N, n = len(targets), robot.n
    Q = np.full((N, n), np.nan)
    ok = np.zeros(N, dtype=bool)
    perr, oerr = np.full(N, np.inf), np.full(N, np.inf)
    code = np.zeros(N, dtype=np.int32)  # the reason of target k is reasons[code[k]]
    reasons: dict[str, int] = {"": 0}
    counts = np.zeros(N, dtype=np.int64)  # with --all: how many solutions each target has
    found: list[np.ndarray] = []  # with --all: each block's solutions, stacked
    rng = np.random.default_rng(args.seed)  # one stream for every block: reproducible
    method = [""]

    def step(s: slice) -> None:
        res = robot.ik(targets[s], rng=rng, all_solutions=args.all, **solve)
        Q[s], ok[s], perr[s], oerr[s] = res.q, res.success, res.position_error, res.orientation_error
        msgs = res.message if isinstance(res.message, list) else [res.message] * (s.stop - s.start)
        code[s] = [reasons.setdefault(m, len(reasons)) for m in msgs]
        if args.all and res.solutions is not None:
            block = [np.atleast_2d(x) for x in res.solutions]
            counts[s] = [len(x) for x in block]
            found.append(np.concatenate(block).reshape(-1, n))
        method[0] = res.method

    _blocks(N, "ik", step)
    fail = np.flatnonzero(~ok)
    closest = _closest(robot, targets, Q, fail, args.seed)
    for k in fail:
        Q[k], perr[k], oerr[k] = closest[k]
    del closest
    if len(fail):
        print(f"robkin: ik: {len(fail)} of {N} targets have no solution (see the 'success' and 'error' "
              f"columns; q there is the closest configuration found)", file=sys.stderr)
    names = [j.name for j in robot.joints]
    text = list(reasons)  # by code

    def out(q: np.ndarray) -> np.ndarray:
        return revolute_degrees(robot, q, to_radians=False) if args.degrees else q

    q_out = out(Q)
    solutions = np.concatenate(found) if found else np.empty((0, n))
    del found
    first = np.concatenate([[0], np.cumsum(counts)])  # target k's solutions: solutions[first[k]:first[k + 1]]
    columns = ["row", "success", *names, "position_error", "orientation_error", "error"]

    def table() -> Iterator[list[Any]]:  # CSV only, one row at a time
        if not args.all:
            for k in range(N):
                yield [k + 1, bool(ok[k]), *q_out[k], perr[k], oerr[k], text[code[k]]]
            return
        for k in range(N):  # every solution numbered from 1; 0 marks a target without one, first
            if not ok[k]:
                yield [k + 1, 0, False, *q_out[k], perr[k], oerr[k], text[code[k]]]
            S = solutions[first[k]:first[k + 1]]
            for i, (x, sol) in enumerate(zip(S, out(S))):
                yield [k + 1, i + 1, True, *sol, *_errors(robot, x, targets[k]), ""]

    def document() -> dict[str, Any]:  # JSON only (at most MAX_JSON_ROWS rows)
        results: list[dict[str, Any]] = [
            {"q": q_out[k], "success": bool(ok[k]), "position_error": perr[k], "orientation_error": oerr[k],
             "reason": text[code[k]] or None} for k in range(N)]
        if args.all:
            for k in range(N):
                results[k]["solutions"] = [{"q": sol} for sol in out(solutions[first[k]:first[k + 1]])]
        return {"joints": names, "method": method[0], "results": results}

    arrays: dict[str, Any] = {"q": q_out, "success": ok, "position_error": perr, "orientation_error": oerr,
                              "error": lambda: np.array(text, dtype=str)[code]}
    if args.all:  # every solution: one CSV row each (numbered), a list per target in JSON, (M, 1 + n) in .npz
        columns.insert(1, "solution")
        arrays["solutions"] = lambda: np.concatenate([np.repeat(np.arange(N), counts)[:, None], out(solutions)],
                                                     axis=1)
    _emit(args, columns, table, arrays, "q", document)
    return 0


def _closest(robot: "Robot", targets: np.ndarray, Q: np.ndarray, rows: np.ndarray,
             seed: int) -> dict[int, tuple[np.ndarray, float, float]]:
    """For targets without a solution: the closest configuration and its distance (length units, rad).

    Where the solver left a configuration (numeric: the best it reached) that is it; where it could
    not (a closed form out of reach gives NaN), a numeric least-squares run finds it, as the GUI shows.
    """
    out: dict[int, tuple[np.ndarray, float, float]] = {}
    missing = [k for k in rows if not np.all(np.isfinite(Q[k]))]
    if missing:
        res = robot.ik(targets[missing], method="numeric", restarts=5, rng=seed)
        Qm = np.atleast_2d(res.q)
        pe, oe = np.atleast_1d(res.position_error), np.atleast_1d(res.orientation_error)
        for i, k in enumerate(missing):
            out[int(k)] = (Qm[i], float(pe[i]), float(oe[i]))
    for k in rows:
        if int(k) not in out:
            out[int(k)] = (Q[k], *_errors(robot, Q[k], targets[k]))
    return out


def _errors(robot: "Robot", q: np.ndarray, T: np.ndarray) -> tuple[float, float]:
    from ... import se3

    F = robot.fk(q)
    return float(np.linalg.norm(T[:3, 3] - F[:3, 3])), float(np.linalg.norm(se3.log_rotation(T[:3, :3] @ F[:3, :3].T)))


def closest_of(robot: "Robot", T: np.ndarray, result: Any, seed: int) -> dict[str, Any]:
    """For one target without a solution: the closest configuration found ``q`` and its
    ``position_error`` (length units) and ``orientation_error`` (radians) from the target."""
    Q = np.atleast_2d(np.asarray(result.q, dtype=float))
    q, pe, oe = _closest(robot, T[None], Q, np.array([0]), seed)[0]
    return {"q": q, "position_error": pe, "orientation_error": oe}
