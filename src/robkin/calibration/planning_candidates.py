"""The configurations a pose plan chooses from: random inside the limits, or read from a file, and kept
where the measuring device sees the marker (a box or a cone in the model's world frame).

- ``random_candidates``: uniform inside the joint limits (``simulation.random_configurations``), drawn
  in rounds until ``count`` of them put the marker inside the ``Region`` (or ``MAX_DRAWS`` were drawn).
- ``read_candidates``: a CSV with a header line, one column per joint named as the model's joints
  (radians, metres for a prismatic joint), one configuration per line; columns x, y, z, qw, qx, qy, qz
  are ignored (a measurement file serves as candidates), any other column is refused. Every value must
  be a finite number inside its joint's limits.
- ``Region``: ``box`` (xmin, xmax, ymin, ymax, zmin, zmax) or ``cone`` (apex x, y, z; axis x, y, z;
  half-angle in degrees; optionally the farthest range in metres): where the measuring device (a laser
  tracker, a camera) sees the marker, in the model's world frame (the robot base of a plain URDF; the
  measuring frame of a calibrated robot).
"""

from __future__ import annotations

import csv
import io
import os
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, quote
from ..robot import Robot
from .simulation import random_configurations

__all__ = ["Region", "parse_region", "random_candidates", "read_candidates", "marker_points", "MAX_CANDIDATES",
           "MAX_DRAWS"]

#: Most candidate configurations read from a file: the exchange costs O(candidates) per step; 10^5 are
#: ~1 min of planning, beyond any useful density for 6-7 joints.
MAX_CANDIDATES = 100_000
#: Most random configurations drawn to find candidates inside a region (10^6 FK evaluations: ~1 s).
MAX_DRAWS = 1_000_000
#: Largest candidate file read (bytes): 10^5 lines of 7 joints in full precision are ~15 MB.
MAX_BYTES = 32 * 1024 * 1024
#: A file value this far outside its joint limit (rad or m) is refused; closer, it is rounding of a
#: value written at the limit (6-9 printed digits).
LIMIT_SLACK = 1e-6
IGNORED_COLUMNS = ("x", "y", "z", "qw", "qx", "qy", "qz")


@dataclass(frozen=True)
class Region:
    """Where the measuring device sees the marker: ``kind`` 'box' or 'cone' and its numbers (see the
    module doc); ``inside(points)`` (N, 3) -> (N,) bool."""

    kind: str
    values: tuple[float, ...]

    def inside(self, points: np.ndarray) -> np.ndarray:
        v = self.values
        if self.kind == "box":
            lo, hi = np.array(v[0::2]), np.array(v[1::2])
            return np.all((points >= lo) & (points <= hi), axis=1)
        apex, axis = np.array(v[:3]), np.array(v[3:6]) / np.linalg.norm(v[3:6])
        d = points - apex
        dist = np.linalg.norm(d, axis=1)
        along = d @ axis
        ok = along >= np.cos(np.radians(v[6])) * dist
        if len(v) > 7:
            ok &= dist <= v[7]
        return ok

    def describe(self) -> str:
        v = self.values
        if self.kind == "box":
            return "x {:g}..{:g} m, y {:g}..{:g} m, z {:g}..{:g} m".format(*v)
        out = f"cone from ({v[0]:g}, {v[1]:g}, {v[2]:g}) m along ({v[3]:g}, {v[4]:g}, {v[5]:g}), half-angle {v[6]:g} deg"
        return out + (f", range {v[7]:g} m" if len(v) > 7 else "")


def parse_region(kind: str, text: str) -> Region:
    """A ``Region`` from an option's text ('--box' / '--cone' and comma-separated numbers); InputError
    naming the option and what is valid."""
    try:
        v = tuple(float(x) for x in text.split(","))
    except ValueError:
        v = ()
    if kind == "box":
        if len(v) != 6 or not all(np.isfinite(v)):
            raise InputError(f"--box: {quote(text)} is not six numbers xmin,xmax,ymin,ymax,zmin,zmax (metres)")
        if not (v[0] < v[1] and v[2] < v[3] and v[4] < v[5]):
            raise InputError(f"--box: {quote(text)} is empty: each minimum must be below its maximum")
        return Region("box", v)
    if len(v) not in (7, 8) or not all(np.isfinite(v)):
        raise InputError(f"--cone: {quote(text)} is not x,y,z,ax,ay,az,half_angle_deg[,range_m] (the device's "
                         f"position, its viewing direction, the half-angle it sees and optionally its range)")
    if not np.linalg.norm(v[3:6]) > 0:
        raise InputError("--cone: the viewing direction ax,ay,az is zero")
    if not 0 < v[6] <= 180:
        raise InputError(f"--cone: half-angle {v[6]:g} deg is not in (0, 180]")
    if len(v) == 8 and not v[7] > 0:
        raise InputError(f"--cone: range {v[7]:g} m is not positive")
    return Region("cone", v)


def marker_points(robot: Robot, q: np.ndarray, marker: np.ndarray | None) -> np.ndarray:
    """The marker (3,) in the tool frame (default its origin) at configurations q (N, n), in the model's
    world frame (N, 3)."""
    T = robot.world @ robot.fk(q)
    m = np.zeros(3) if marker is None else np.asarray(marker, dtype=float)
    return T[:, :3, :3] @ m + T[:, :3, 3]


def random_candidates(robot: Robot, count: int, rng: np.random.Generator, region: Region | None = None,
                      marker: np.ndarray | None = None, needed: int = 1) -> np.ndarray:
    """``count`` configurations (count, n) uniform inside the joint limits whose marker lies in ``region``;
    fewer if ``MAX_DRAWS`` draws do not find them all, InputError if fewer than ``needed``."""
    if region is None:
        return random_configurations(robot, count, rng)
    found: list[np.ndarray] = []
    have = drawn = 0
    batch = max(count, 1000)
    while have < count and drawn < MAX_DRAWS:
        q = random_configurations(robot, batch, rng)
        drawn += batch
        ok = q[region.inside(marker_points(robot, q, marker))]
        found.append(ok)
        have += len(ok)
        if have == 0 and drawn >= 20 * batch:   # nothing in 20 rounds: the region is out of reach
            break
    Q = np.concatenate(found)[:count]
    if len(Q) < needed:
        raise InputError(f"--{region.kind}: only {len(Q)} of {drawn} random configurations put the marker inside "
                         f"({region.describe()}); {needed} are needed: is the region in the model's world frame "
                         f"and within reach?")
    return Q


def read_candidates(path: str | os.PathLike[str], robot: Robot) -> np.ndarray:
    """Candidate configurations (C, n) from a CSV file (see the module doc); InputError naming the file,
    line and column otherwise."""
    from ..io.files.input_files import read_text_file
    from ..io.tables.cells import csv_read_cell

    src = os.fspath(path)
    text = read_text_file(src, MAX_BYTES, "a candidates file")
    if "\0" in text:
        raise InputError(f"{src}: holds a NUL character; a candidates file is CSV text")
    names = [j.name for j in robot.joints]
    header: list[str] | None = None
    rows: list[list[float]] = []
    try:
        records = list(csv.reader(io.StringIO(text)))
    except csv.Error as exc:
        raise InputError(f"{src}: not CSV ({exc})") from None
    lim = np.array(robot.limits, dtype=float)
    for line_no, record in enumerate(records, start=1):
        if not record or not "".join(record).strip() or record[0].lstrip().startswith("#"):
            continue
        if header is None:
            header = [csv_read_cell(h.strip()) for h in record]
            _check_header(header, names, src)
            index = [header.index(n) for n in names]
            continue
        if len(record) != len(header):
            raise InputError(f"{src}: line {line_no}: {len(record)} values for {len(header)} columns")
        row = []
        for k, col in zip(index, names):
            cell = record[k].strip()
            try:
                v = float(cell)
            except ValueError:
                raise InputError(f"{src}: line {line_no}, column {quote(col)}: {quote(cell)} is not a number") from None
            j = names.index(col)
            if not (lim[j, 0] - LIMIT_SLACK <= v <= lim[j, 1] + LIMIT_SLACK):   # also NaN
                raise InputError(f"{src}: line {line_no}, column {quote(col)}: {quote(cell)} is not a finite value "
                                 f"inside the joint's limits [{lim[j, 0]:g}, {lim[j, 1]:g}]")
            row.append(v)
        rows.append(row)
        if len(rows) > MAX_CANDIDATES:
            raise InputError(f"{src}: more than {MAX_CANDIDATES} candidate configurations")
    if header is None or not rows:
        raise InputError(f"{src}: no candidates; expected a header line {', '.join(names)} and one configuration "
                         f"per line")
    return np.clip(np.array(rows, dtype=float), lim[:, 0], lim[:, 1])


def _check_header(header: list[str], names: list[str], src: str) -> None:
    known = set(names) | set(IGNORED_COLUMNS)
    for h in header:
        if h not in known:
            raise InputError(f"{src}: column {quote(h)} is not a joint of the model ({', '.join(names)}); "
                             f"x, y, z, qw, qx, qy, qz are ignored, nothing else is allowed")
    if len(set(header)) != len(header):
        dup = next(h for h in header if header.count(h) > 1)
        raise InputError(f"{src}: column {quote(dup)} appears twice")
    missing = [n for n in names if n not in header]
    if missing:
        raise InputError(f"{src}: no column {', '.join(quote(c) for c in missing[:4])}; expected one per joint: "
                         f"{', '.join(names)}")
