# cython: language_level=3
"""Frame placement for the DH-type conversions: common normals, the canonical DH/MDH rules, parameters.

The one implementation of the rules documented in ``robkin.representations.frames`` (which wraps the
single-pair functions here) and of the DH / MDH frame chains that ``dh_from_robot`` and
``dh_from_robots`` (and their MDH twins) use, one robot or a batch of robots per call. The tolerances
are those of ``robkin.lines`` and ``robkin.representations.frames``; their reasons are stated there.

The C code sits in two included files, so that it stays one extension module (static, inlinable C
functions; nothing more to load on ``robkin convert``): ``frame_geometry.pxi``, the line geometry
(closest points, classification, frames from z and x), and ``dh_placement.pxi``, the DH / MDH rules
(common-normal frames, parameters between frames, link matrices, the frame chains). ``table_pipeline.pxi`` holds the stages after the placement
(rounding, residual tool, FK self-check) that ``convert_tables`` and ``check_tables`` run one robot
after another, on several threads for a large batch. This file holds the tolerances and the Python
entry points.

Poses are row-major ``double[16]`` as in ``linalg.pxd``; frame columns x, y, z are T[0, 4, 8],
T[1, 5, 9], T[2, 6, 10] and the origin T[3, 7, 11]. The arithmetic follows the Python statements of
the documented rules step by step (no -ffast-math), so results agree with them to rounding.
"""

cimport numpy as cnp
from libc.math cimport sqrt, sin, cos, atan2, fabs, M_PI
from robkin.compiled.runtime.linalg cimport dot3, norm3, cross3, tf_identity, tf_copy, tf_mul
from robkin.compiled.chain.fk cimport tool_poses
from robkin.compiled.runtime.threads cimport batch_threads
from cython.parallel cimport prange
from libc.stdlib cimport malloc, free

import numpy as np

cnp.import_array()

from robkin.lines import ANGLE_TOL as _ANGLE_TOL, LENGTH_TOL as _LENGTH_TOL
from robkin.compiled.conversions.tolerances import (KEEP_TOL as _KEEP_TOL, TIE_TOL as _TIE_TOL,
                                                    SNAP_BUDGET as _SNAP_BUDGET, SNAP_WINDOW as _SNAP_WINDOW)

# the tolerances of robkin.lines and robkin.representations.frames, read from there (reasons stated there)
cdef double ANGLE_TOL = _ANGLE_TOL
cdef double LENGTH_TOL = _LENGTH_TOL
cdef double KEEP_TOL = _KEEP_TOL
cdef double TIE_TOL = _TIE_TOL
#: sin of a tilt of joint 1 from the base z axis below which it is rounding noise of a unit vector
#: (~1e-16 per component), not geometry: no tilted MDH base frame is made for it.
cdef double NOISE_TILT = 1e-15
#: An MDH frame {0} on the base z axis farther than this many robot sizes from the base comes from a
#: joint 1 axis nearly parallel to that axis (the common normal lies ~offset / tilt away): the base is
#: then tilted onto joint 1's axis instead, which keeps every length of the table short.
cdef double FAR = 10.0

include "frame_geometry.pxi"
include "dh_placement.pxi"
include "table_pipeline.pxi"

#: Robots per thread below which a batch conversion stays on fewer threads: a 6-joint robot's table
#: costs ~5 us here and its FK check ~11 us (benchmarks/bench_convert.py, "by part"), so 16 robots are
#: ~0.25 ms of work per thread, far above the ~10 us of waking a thread team.
MIN_ROBOTS_PER_THREAD = 16


# ---- Python entry points: inputs are converted to contiguous float64 once, nothing else is checked
# (the callers in robkin.representations pass arrays they built themselves)

cdef inline cnp.ndarray _f64(x):
    return np.ascontiguousarray(x, dtype=np.float64)


cdef inline double* _ptr(cnp.ndarray a) noexcept:
    return <double*>cnp.PyArray_DATA(a)


def common_normal_frame(p_a, u_a, p_b, u_b, bint on_b, prev, double scale, keep=None):
    """Frame (4, 4) on line A (``on_b`` false) or B whose x is the common normal from A to B, or
    ``keep`` (4, 4) when it satisfies the convention (``representations.frames.common_normal_frame``)."""
    cdef cnp.ndarray pa = _f64(p_a), ua = _f64(u_a), pb = _f64(p_b), ub = _f64(u_b), pv = _f64(prev)
    cdef cnp.ndarray kp = None if keep is None else _f64(keep)
    out = np.empty((4, 4))
    normal_frame_c(_ptr(pa), _ptr(ua), _ptr(pb), _ptr(ub), on_b, _ptr(pv), scale,
                   NULL if kp is None else _ptr(kp), _ptr(out))
    return out


def satisfies_normal(frame, p_other, u_other, double scale, double tol=_KEEP_TOL):
    """Does the frame's x axis cross the line (p_other, u_other) at a right angle (to tol)?"""
    cdef cnp.ndarray f = _f64(frame), p = _f64(p_other), u = _f64(u_other)
    return bool(satisfies(_ptr(f), _ptr(p), _ptr(u), scale, tol))


def x_line_on(prev, p, u):
    """Where the x axis of ``prev`` (4, 4) meets the line (p, u); the foot of prev's origin if they miss."""
    cdef cnp.ndarray T = _f64(prev), pp = _f64(p), uu = _f64(u)
    out = np.empty(3)
    x_line_meet(_ptr(T), _ptr(pp), _ptr(uu), _ptr(out))
    return out


def frame_from_zx(origin, z, x):
    """Pose (4, 4) with the given origin, unit z, and x made exactly orthogonal to z and unit."""
    cdef cnp.ndarray o = _f64(origin), zz = _f64(z), xx = _f64(x)
    out = np.empty((4, 4))
    from_zx(_ptr(o), _ptr(zz), _ptr(xx), _ptr(out))
    return out


def dh_params_between(prev, frame):
    """(a, d, alpha, theta) with prev^-1 frame = Rz(theta) Tz(d) Tx(a) Rx(alpha)."""
    cdef cnp.ndarray A = _f64(prev), B = _f64(frame)
    cdef double row[4]
    dh_params_c(_ptr(A), _ptr(B), row)
    return row[0], row[1], row[2], row[3]


def mdh_params_between(prev, frame):
    """(a, d, alpha, theta) with prev^-1 frame = Rx(alpha) Tx(a) Rz(theta) Tz(d)."""
    cdef cnp.ndarray A = _f64(prev), B = _f64(frame)
    cdef double row[4]
    mdh_params_c(_ptr(A), _ptr(B), row)
    return row[0], row[1], row[2], row[3]


def approx_dh_params(prev, target):
    """A DH row (a, d, alpha, theta) moving ``prev`` towards ``target`` (the paper's last-row rule)."""
    cdef cnp.ndarray A = _f64(prev), B = _f64(target)
    cdef double row[4]
    approx_dh_c(_ptr(A), _ptr(B), row)
    return row[0], row[1], row[2], row[3]


def _batch(cand, scale, keep):
    cdef cnp.ndarray C = _f64(cand), S = _f64(scale)
    cdef cnp.ndarray K = np.ascontiguousarray(keep, dtype=np.uint8)
    if C.ndim != 4 or C.shape[1] < 1 or C.shape[2] != 4 or C.shape[3] != 4 or S.ndim != 1 \
            or K.ndim != 1 or S.shape[0] != C.shape[0] or K.shape[0] != C.shape[0]:
        raise ValueError("expected cand (B, n, 4, 4), scale (B,) and keep (B,)")
    return C, S, K


def placement(bint modified, cand, tool, scale, keep):
    """Standard (``modified`` false) or modified DH frames and rows of B robots with n joints each.

    Parameters
    ----------
    cand : (B, n, 4, 4) float array
        Each robot's joint frames, turned by pi about x for flipped joints.
    tool : (B, 4, 4) float array
        Each robot's tool pose (standard DH's last frame depends on it; modified DH's does not).
    scale : (B,) float array
        Each robot's size (``Robot.scale``), for the relative length tolerances.
    keep : (B,) bool array
        Keep a robot's own frames where they satisfy the convention (they came from a table of the
        same kind).

    Returns
    -------
    frames : (B, n + 1, 4, 4)
        Frames {0}..{n}; {n} is the last frame before the residual tool.
    rows : (B, n, 4)
        (a, d, alpha, theta) between consecutive frames, not yet rounded.
    """
    cdef cnp.ndarray C, S, K
    C, S, K = _batch(cand, scale, keep)
    cdef cnp.ndarray T = _f64(tool)
    cdef Py_ssize_t B = C.shape[0], n = C.shape[1], k
    if T.ndim != 3 or T.shape[0] != B or T.shape[1] != 4 or T.shape[2] != 4:
        raise ValueError("expected tool (B, 4, 4)")
    F = np.empty((B, n + 1, 4, 4))
    R = np.empty((B, n, 4))
    cdef double* c = _ptr(C)
    cdef double* t = _ptr(T)
    cdef double* s = _ptr(S)
    cdef unsigned char* kp = <unsigned char*>cnp.PyArray_DATA(K)
    cdef double* f = _ptr(F)
    cdef double* r = _ptr(R)
    with nogil:
        for k in range(B):
            if modified:
                mdh_chain(c + 16 * n * k, n, s[k], kp[k], f + 16 * (n + 1) * k, r + 4 * n * k)
            else:
                dh_chain(c + 16 * n * k, n, t + 16 * k, s[k], kp[k], f + 16 * (n + 1) * k, r + 4 * n * k)
    return F, R


def robots_fk(L, revolute, Q, int threads=0):
    """Tool poses (B, m, 4, 4) of B robots with n joints each at m configurations each: the robots' own
    compiled FK (``Robot.fk``: the walk of ``fk.pxd``), for the conversions' FK self-check.

    Parameters
    ----------
    L : (B, n + 1, 4, 4) float array
        Each robot's fixed transforms (``robot.local_transforms`` of its frames).
    revolute : (B, n) bool array
    Q : (B, m, n) float array
        Joint values (rad or length units); finite.
    threads : int
        At most this many threads (<= 0: automatic, ``robkin.threads``); the same bits with any.
    """
    cdef cnp.ndarray La = _f64(L), Qa = _f64(Q)
    cdef cnp.ndarray ra = np.ascontiguousarray(revolute, dtype=np.uint8)
    if La.ndim != 4 or Qa.ndim != 3 or ra.ndim != 2 or La.shape[0] != Qa.shape[0] \
            or ra.shape[0] != Qa.shape[0] or La.shape[1] != Qa.shape[2] + 1 or ra.shape[1] != Qa.shape[2] \
            or La.shape[2] != 4 or La.shape[3] != 4 or Qa.shape[2] < 1:
        raise ValueError("expected L (B, n+1, 4, 4), revolute (B, n) and Q (B, m, n)")
    cdef Py_ssize_t B = Qa.shape[0], m = Qa.shape[1], n = Qa.shape[2], k
    out = np.empty((B, m, 4, 4))
    cdef double* l = _ptr(La)
    cdef double* q = _ptr(Qa)
    cdef unsigned char* r = <unsigned char*>cnp.PyArray_DATA(ra)
    cdef double* o = _ptr(out)
    cdef int nt = batch_threads(threads, B, MIN_ROBOTS_PER_THREAD)
    with nogil:
        for k in prange(B, num_threads=nt, schedule="dynamic", chunksize=8):  # one block walk per robot
            tool_poses(l + 16 * (n + 1) * k, r + n * k, <int>n, q + n * m * k, m, o + 16 * m * k)
    return out


def tables_fk(bint modified, base, rows, tool, revolute, sign, Q):
    """Tool poses (B, m, 4, 4) of B standard (``modified`` false) or modified DH tables with n joints
    each at m configurations each, from their rows: base A_1(q_1) ... A_n(q_n) tool, where a revolute
    joint adds sign * q to theta and a prismatic one to d (``LinkTable.fk``, compiled for the
    conversions' FK self-check).

    Parameters
    ----------
    base, tool : (B, 4, 4) float arrays
    rows : (B, n, 4) float array
        (a, d, alpha, theta) per joint.
    revolute : (B, n) bool array
    sign : (B, n) float array
        +1, or -1 for a flipped joint.
    Q : (B, m, n) float array
    """
    cdef cnp.ndarray Ba = _f64(base), Ra = _f64(rows), Ta = _f64(tool), Sa = _f64(sign), Qa = _f64(Q)
    cdef cnp.ndarray ra = np.ascontiguousarray(revolute, dtype=np.uint8)
    if Qa.ndim != 3 or Ra.ndim != 3 or Ba.ndim != 3 or Ta.ndim != 3 or ra.ndim != 2 or Sa.ndim != 2:
        raise ValueError("expected base, tool (B, 4, 4), rows (B, n, 4), revolute, sign (B, n), Q (B, m, n)")
    cdef Py_ssize_t B = Qa.shape[0], m = Qa.shape[1], n = Qa.shape[2], k, c, i
    if Ra.shape[0] != B or Ra.shape[1] != n or Ra.shape[2] != 4 or Ba.shape[0] != B or Ta.shape[0] != B \
            or Ba.shape[1] != 4 or Ba.shape[2] != 4 or Ta.shape[1] != 4 or Ta.shape[2] != 4 \
            or ra.shape[0] != B or ra.shape[1] != n or Sa.shape[0] != B or Sa.shape[1] != n:
        raise ValueError("expected base, tool (B, 4, 4), rows (B, n, 4), revolute, sign (B, n), Q (B, m, n)")
    out = np.empty((B, m, 4, 4))
    cdef double* bp = _ptr(Ba)
    cdef double* rp = _ptr(Ra)
    cdef double* tp = _ptr(Ta)
    cdef double* sp = _ptr(Sa)
    cdef double* qp = _ptr(Qa)
    cdef unsigned char* rev = <unsigned char*>cnp.PyArray_DATA(ra)
    cdef double* o = _ptr(out)
    cdef double row[4]
    cdef double A[16]
    cdef double T[16]
    cdef double U[16]
    cdef double q
    with nogil:
        for k in range(B):
            for c in range(m):
                tf_copy(bp + 16 * k, T)
                for i in range(n):
                    row[0], row[1], row[2], row[3] = (rp[4 * (n * k + i)], rp[4 * (n * k + i) + 1],
                                                      rp[4 * (n * k + i) + 2], rp[4 * (n * k + i) + 3])
                    q = sp[n * k + i] * qp[n * (m * k + c) + i]
                    if rev[n * k + i]:
                        row[3] = row[3] + q
                    else:
                        row[1] = row[1] + q
                    if modified:
                        mdh_matrix_c(row, A)
                    else:
                        dh_matrix_c(row, A)
                    tf_mul(T, A, U)
                    tf_copy(U, T)
                tf_mul(T, tp + 16 * k, o + 16 * (m * k + c))
    return out


def _joint_array(J, Py_ssize_t B, Py_ssize_t n):
    cdef cnp.ndarray a = _f64(J)
    if a.ndim != 3 or a.shape[0] != B or a.shape[1] != n or a.shape[2] != 4:
        raise ValueError("expected joints (B, n, 4)")
    return a


def convert_tables(bint modified, frames, joints, keep, snap, scale, flip_x, int threads=0):
    """Rows, base and residual tool of B standard (``modified`` false) or modified DH tables, each
    robot with n joints: the frame placement (``placement``), the rounding of near-round values for
    the robots with ``snap`` (``rounding.snap_many``) and the residual tool
    (``link_table.residual_tool``), one robot after another in C.

    Parameters
    ----------
    frames : (B, n + 1, 4, 4) float array
        Each robot's GJD frames (joint frames, then the tool pose).
    joints : (B, n, 4) float array
        Per joint: revolute (1 or 0), flip (1 or 0), lower and upper limit (-inf / +inf for none).
    keep, snap : (B,) bool arrays
        Keep the robot's own frames where they satisfy the convention; round near-round values.
    scale : (B,) float array
        Each robot's size (``Robot.scale``).
    flip_x : (4, 4) float array
        ``link_table.FLIP_X``.
    threads : int
        At most this many threads (<= 0: automatic, ``robkin.threads``); the same bits with any.

    Returns
    -------
    rows : (B, n, 4), base : (B, 4, 4), tool : (B, 4, 4)
    """
    cdef cnp.ndarray Fa = _f64(frames)
    if Fa.ndim != 4 or Fa.shape[1] < 2 or Fa.shape[2] != 4 or Fa.shape[3] != 4:
        raise ValueError("expected frames (B, n + 1, 4, 4)")
    cdef Py_ssize_t B = Fa.shape[0], n = Fa.shape[1] - 1, k, i
    cdef cnp.ndarray Ja = _joint_array(joints, B, n), Xa = _f64(flip_x)
    cdef cnp.ndarray Ka = np.ascontiguousarray(keep, dtype=np.uint8)
    cdef cnp.ndarray Na = np.ascontiguousarray(snap, dtype=np.uint8), Sa = _f64(scale)
    if Ka.shape[0] != B or Na.shape[0] != B or Sa.shape[0] != B or Xa.size != 16:
        raise ValueError("expected keep, snap, scale (B,) and flip_x (4, 4)")
    rows = np.empty((B, n, 4))
    base = np.empty((B, 4, 4))
    tool = np.empty((B, 4, 4))
    cdef double* f = _ptr(Fa)
    cdef double* j = _ptr(Ja)
    cdef double* x = _ptr(Xa)
    cdef unsigned char* kp = <unsigned char*>cnp.PyArray_DATA(Ka)
    cdef unsigned char* np_ = <unsigned char*>cnp.PyArray_DATA(Na)
    cdef double* s = _ptr(Sa)
    cdef double* r = _ptr(rows)
    cdef double* b = _ptr(base)
    cdef double* t = _ptr(tool)
    cdef int nt = batch_threads(threads, B, MIN_ROBOTS_PER_THREAD)
    cdef double* work
    cdef unsigned char* flip
    cdef double* trav
    cdef Py_ssize_t size = 48 * n + 16 + 2 * n
    with nogil:
        for k in prange(B, num_threads=nt, schedule="dynamic", chunksize=8):
            work = <double*>malloc(size * sizeof(double))
            if work == NULL:
                continue   # reported below: a table of NaN
            trav = work + 48 * n + 16
            flip = <unsigned char*>(trav + n)
            for i in range(n):
                flip[i] = j[4 * (n * k + i) + 1] > 0
                trav[i] = 0.0 if j[4 * (n * k + i)] > 0 else max(fabs(j[4 * (n * k + i) + 2]),
                                                                   fabs(j[4 * (n * k + i) + 3]))
            table_of_robot(modified, f + 16 * (n + 1) * k, n, flip, x, trav, s[k], kp[k], np_[k],
                           r + 4 * n * k, t + 16 * k, work)
            tf_copy(work + 32 * n, b + 16 * k)
            free(work)
    return rows, base, tool


def check_tables(bint modified, base, rows, tool, L, joints, scale, U, int threads=0):
    """The FK self-check of B standard (``modified`` false) or modified DH tables with n joints each:
    each table's FK from its rows against its robot's compiled FK at q = 0 and the sample U scaled to
    the joints' ranges (``link_table.sample_configurations``), and each table's longest length.

    Parameters
    ----------
    base, tool : (B, 4, 4) float arrays
    rows : (B, n, 4) float array
    L : (B, n + 1, 4, 4) float array
        Each robot's fixed transforms (``frame_stacks.local_transforms``, ``Robot._local``).
    joints : (B, n, 4) float array
        As for ``convert_tables``.
    scale : (B,) float array
    U : (m, n) float array
        ``samples.unit_sample(m, n)``.
    threads : int
        As for ``convert_tables``.

    Returns
    -------
    err : (B,) float array
        ``link_table.pose_difference`` of the table's FK from the robot's over the m + 1
        configurations (length units).
    length : (B,) float array
        The largest |a|, |d| and base / tool offset of each table.
    """
    cdef cnp.ndarray Ra = _f64(rows), Ba = _f64(base), Ta = _f64(tool), La = _f64(L), Sa = _f64(scale)
    cdef cnp.ndarray Ua = _f64(U)
    if Ra.ndim != 3 or Ra.shape[2] != 4:
        raise ValueError("expected rows (B, n, 4)")
    cdef Py_ssize_t B = Ra.shape[0], n = Ra.shape[1], k, i, m
    cdef cnp.ndarray Ja = _joint_array(joints, B, n)
    if Ba.size != 16 * B or Ta.size != 16 * B or La.size != 16 * (n + 1) * B or Sa.shape[0] != B \
            or Ua.ndim != 2 or Ua.shape[1] != n:
        raise ValueError("expected base, tool (B, 4, 4), L (B, n + 1, 4, 4), scale (B,), U (m, n)")
    m = Ua.shape[0]
    err = np.empty(B)
    length = np.empty(B)
    cdef double* b = _ptr(Ba)
    cdef double* r = _ptr(Ra)
    cdef double* t = _ptr(Ta)
    cdef double* l = _ptr(La)
    cdef double* j = _ptr(Ja)
    cdef double* s = _ptr(Sa)
    cdef double* u = _ptr(Ua)
    cdef double* e = _ptr(err)
    cdef double* g = _ptr(length)
    cdef int nt = batch_threads(threads, B, MIN_ROBOTS_PER_THREAD)
    cdef double* work
    cdef unsigned char* rev
    cdef Py_ssize_t size = (m + 1) * n + 32 * (m + 1) + 4 * n + n
    with nogil:
        for k in prange(B, num_threads=nt, schedule="dynamic", chunksize=8):
            work = <double*>malloc(size * sizeof(double))
            if work == NULL:
                e[k] = INFINITY   # reported as an FK error by the caller
                continue
            rev = <unsigned char*>(work + (m + 1) * n + 32 * (m + 1) + 3 * n)
            for i in range(n):
                rev[i] = j[4 * (n * k + i)] > 0
                work[(m + 1) * n + 32 * (m + 1) + i] = -1.0 if j[4 * (n * k + i) + 1] > 0 else 1.0
                work[(m + 1) * n + 32 * (m + 1) + n + 2 * i] = j[4 * (n * k + i) + 2]
                work[(m + 1) * n + 32 * (m + 1) + n + 2 * i + 1] = j[4 * (n * k + i) + 3]
            check_of_table(modified, b + 16 * k, r + 4 * n * k, t + 16 * k, l + 16 * (n + 1) * k, n, rev,
                           work + (m + 1) * n + 32 * (m + 1), work + (m + 1) * n + 32 * (m + 1) + n,
                           s[k], u, m, work, work + (m + 1) * n, e + k, g + k)
            free(work)
    return err, length

