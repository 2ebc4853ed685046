# cython: language_level=3
"""Frame placement for the DH-type conversions: common normals, the canonical DH/MDH rules, parameters.

The one implementation of the rules documented in ``robkin.representations.frames`` (which wraps the
single-pair functions here) and of the DH / MDH frame chains that ``dh_from_robot`` and
``dh_from_robots`` (and their MDH twins) use, one robot or a batch of robots per call. The tolerances
are those of ``robkin.lines`` and ``robkin.representations.frames``; their reasons are stated there.

Poses are row-major ``double[16]`` as in ``linalg.pxd``; frame columns x, y, z are T[0, 4, 8],
T[1, 5, 9], T[2, 6, 10] and the origin T[3, 7, 11]. The arithmetic follows the Python statements of
the documented rules step by step (no -ffast-math), so results agree with them to rounding.
"""

cimport numpy as cnp
from libc.math cimport sqrt, sin, cos, atan2, fabs, M_PI
from robkin.compiled.linalg cimport dot3, norm3, cross3, tf_identity, tf_copy, tf_mul
from robkin.compiled.fk cimport walk_tool

import numpy as np

cnp.import_array()

from robkin.lines import ANGLE_TOL as _ANGLE_TOL, LENGTH_TOL as _LENGTH_TOL
from robkin.representations.frames import KEEP_TOL as _KEEP_TOL, TIE_TOL as _TIE_TOL

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

cdef enum Relation:
    SKEW, INTERSECTING, PARALLEL, ANTI_PARALLEL, COINCIDENT, ANTI_COINCIDENT


cdef inline void col(const double* T, int j, double* out) noexcept nogil:
    out[0] = T[j]
    out[1] = T[4 + j]
    out[2] = T[8 + j]


cdef inline void foot(const double* point, const double* p, const double* u, double* out) noexcept nogil:
    """Foot of the perpendicular from point onto the line (p, u), u unit."""
    cdef double w[3]
    w[0] = point[0] - p[0]
    w[1] = point[1] - p[1]
    w[2] = point[2] - p[2]
    cdef double t = dot3(w, u)
    out[0] = p[0] + t * u[0]
    out[1] = p[1] + t * u[1]
    out[2] = p[2] + t * u[2]


cdef double closest(const double* p1, const double* u1, const double* p2, const double* u2,
                    double* c1, double* c2) noexcept nogil:
    """Closest points c1 on line 1 and c2 on line 2 of two non-parallel lines; returns their distance.

    Line 1 is re-anchored at the foot of p2 first (see ``robkin.lines.closest_points`` for why)."""
    cdef double s = (p2[0] - p1[0]) * u1[0] + (p2[1] - p1[1]) * u1[1] + (p2[2] - p1[2]) * u1[2]
    cdef double ax = p1[0] + s * u1[0], ay = p1[1] + s * u1[1], az = p1[2] + s * u1[2]
    cdef double wx = ax - p2[0], wy = ay - p2[1], wz = az - p2[2]
    cdef double b = u1[0] * u2[0] + u1[1] * u2[1] + u1[2] * u2[2]
    cdef double d1 = u1[0] * wx + u1[1] * wy + u1[2] * wz
    cdef double d2 = u2[0] * wx + u2[1] * wy + u2[2] * wz
    cdef double nx = u1[1] * u2[2] - u1[2] * u2[1], ny = u1[2] * u2[0] - u1[0] * u2[2]
    cdef double nz = u1[0] * u2[1] - u1[1] * u2[0]
    cdef double det = nx * nx + ny * ny + nz * nz
    cdef double t1 = (b * d2 - d1) / det
    cdef double t2 = (d2 - b * d1) / det
    c1[0] = ax + t1 * u1[0]
    c1[1] = ay + t1 * u1[1]
    c1[2] = az + t1 * u1[2]
    c2[0] = p2[0] + t2 * u2[0]
    c2[1] = p2[1] + t2 * u2[1]
    c2[2] = p2[2] + t2 * u2[2]
    return sqrt((c2[0] - c1[0]) ** 2 + (c2[1] - c1[1]) ** 2 + (c2[2] - c1[2]) ** 2)


cdef inline double sin_between(const double* a, const double* b) noexcept nogil:
    cdef double n[3]
    cross3(a, b, n)
    return norm3(n)


cdef Relation classify(const double* p1, const double* u1, const double* p2, const double* u2,
                       double scale) noexcept nogil:
    """How line 2 relates to line 1 (``robkin.lines.classify``)."""
    cdef bint parallel = sin_between(u1, u2) < ANGLE_TOL
    cdef bint same_sense = dot3(u1, u2) > 0
    cdef double f[3]
    cdef double c1[3]
    cdef double c2[3]
    cdef double dist
    if parallel:  # the common normal through p1
        foot(p1, p2, u2, f)
        dist = sqrt((f[0] - p1[0]) ** 2 + (f[1] - p1[1]) ** 2 + (f[2] - p1[2]) ** 2)
    else:
        dist = closest(p1, u1, p2, u2, c1, c2)
    cdef bint meet = dist <= LENGTH_TOL * (scale if scale > 1e-300 else 1e-300)
    if parallel:
        if meet:
            return COINCIDENT if same_sense else ANTI_COINCIDENT
        return PARALLEL if same_sense else ANTI_PARALLEL
    return INTERSECTING if meet else SKEW


cdef void from_zx(const double* origin, const double* z, const double* x, double* T) noexcept nogil:
    """Pose with the given origin, unit z, and x made orthogonal to z and unit (Gram-Schmidt twice:
    see ``robkin.representations.frames.frame_from_zx``)."""
    cdef double k = sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2])
    cdef double zx = z[0] / k, zy = z[1] / k, zz = z[2] / k
    cdef double xx = x[0], xy = x[1], xz = x[2], c
    cdef int it
    for it in range(2):
        c = xx * zx + xy * zy + xz * zz
        xx, xy, xz = xx - c * zx, xy - c * zy, xz - c * zz
        k = sqrt(xx * xx + xy * xy + xz * xz)
        xx, xy, xz = xx / k, xy / k, xz / k
    T[0], T[1], T[2], T[3] = xx, zy * xz - zz * xy, zx, origin[0]
    T[4], T[5], T[6], T[7] = xy, zz * xx - zx * xz, zy, origin[1]
    T[8], T[9], T[10], T[11] = xz, zx * xy - zy * xx, zz, origin[2]
    T[12], T[13], T[14], T[15] = 0.0, 0.0, 0.0, 1.0


cdef bint satisfies(const double* frame, const double* p_other, const double* u_other,
                    double scale, double tol) noexcept nogil:
    """Does the frame's x axis cross the line (p_other, u_other) at a right angle (to tol, and
    tol * scale for the distance)?"""
    cdef double o[3]
    cdef double x[3]
    cdef double c1[3]
    cdef double c2[3]
    col(frame, 3, o)
    col(frame, 0, x)
    if fabs(dot3(x, u_other)) > tol:
        return False
    if sin_between(x, u_other) < ANGLE_TOL:  # x along the other line: cannot cross it
        return False
    return closest(o, x, p_other, u_other, c1, c2) <= tol * scale


cdef inline void choose_sign(double* x, const double* x_pref, const double* y_pref) noexcept nogil:
    """x or -x, whichever keeps |theta| <= pi/2 from x_pref (ties: theta = +pi/2 towards y_pref)."""
    cdef double c = dot3(x, x_pref)
    cdef bint flip
    if fabs(c) > TIE_TOL:
        flip = not (c > 0)
    else:
        flip = not (dot3(x, y_pref) >= 0)
    if flip:
        x[0], x[1], x[2] = -x[0], -x[1], -x[2]


cdef void x_line_meet(const double* prev, const double* p, const double* u, double* out) noexcept nogil:
    """Where prev's x axis meets the line (p, u); the foot of prev's origin if they miss."""
    cdef double o[3]
    cdef double x[3]
    cdef double c1[3]
    col(prev, 3, o)
    col(prev, 0, x)
    if sin_between(x, u) < ANGLE_TOL:
        foot(o, p, u, out)
    else:
        closest(o, x, p, u, c1, out)


cdef void perpendicular(const double* u, double* out) noexcept nogil:
    """A unit vector normal to unit u, from the coordinate axis least aligned with u (first on ties)."""
    cdef int k = 0, i
    for i in range(1, 3):
        if fabs(u[i]) < fabs(u[k]):
            k = i
    cdef double e[3]
    e[0], e[1], e[2] = 0.0, 0.0, 0.0
    e[k] = 1.0
    cdef double c = dot3(e, u)
    for i in range(3):
        out[i] = e[i] - c * u[i]
    c = norm3(out)
    for i in range(3):
        out[i] = out[i] / c


cdef void normal_frame_c(const double* p_a, const double* u_a, const double* p_b, const double* u_b,
                         bint on_b, const double* prev, double scale, const double* keep,
                         double* out) noexcept nogil:
    """Frame on line A (on_b false) or B whose x is the common normal from A to B; ``keep`` (or NULL)
    is returned when it satisfies the convention (``frames.common_normal_frame``)."""
    cdef const double* u_self = u_b if on_b else u_a
    cdef const double* u_other = u_a if on_b else u_b
    cdef const double* p_other = p_a if on_b else p_b
    if keep != NULL and satisfies(keep, p_other, u_other, scale, KEEP_TOL):
        tf_copy(keep, out)
        return
    cdef double x_prev[3]
    cdef double o_prev[3]
    cdef double anchor[3]
    cdef double y_ref[3]
    cdef double x[3]
    cdef double f[3]
    cdef double c1[3]
    cdef double c2[3]
    cdef double dist, c
    cdef int i
    col(prev, 0, x_prev)
    col(prev, 3, o_prev)
    if on_b:  # where the previous frame meets line A: its origin (DH), or where its x crosses A (MDH)
        foot(o_prev, p_a, u_a, anchor)
    else:
        x_line_meet(prev, p_a, u_a, anchor)
    cross3(u_a, x_prev, y_ref)
    cdef Relation rel = classify(p_a, u_a, p_b, u_b, scale)
    if rel == PARALLEL or rel == ANTI_PARALLEL:
        foot(anchor, p_b, u_b, f)
        for i in range(3):
            x[i] = f[i] - anchor[i]
        dist = norm3(x)
        # measured from the anchor the lines may still meet to rounding: then they are coincident
        if dist > LENGTH_TOL * scale:
            for i in range(3):
                x[i] = x[i] / dist  # unit before the sign test (its tie margin is on a cosine)
            choose_sign(x, x_prev, y_ref)
            if on_b:
                from_zx(f, u_self, x, out)
            else:
                from_zx(anchor, u_self, x, out)
            return
        rel = COINCIDENT
    if rel == COINCIDENT or rel == ANTI_COINCIDENT:
        c = dot3(x_prev, u_self)
        for i in range(3):
            x[i] = x_prev[i] - c * u_self[i]
        if norm3(x) < 1e-6:  # prev x along the axis (cannot happen for a valid chain)
            perpendicular(u_self, x)
        if on_b:
            foot(anchor, p_b, u_b, f)
            from_zx(f, u_self, x, out)
        else:
            from_zx(anchor, u_self, x, out)
        return
    closest(p_a, u_a, p_b, u_b, c1, c2)
    cross3(u_a, u_b, x)
    dist = norm3(x)
    for i in range(3):
        x[i] = x[i] / dist
    choose_sign(x, x_prev, y_ref)
    if on_b:
        from_zx(c2, u_self, x, out)
    else:
        from_zx(c1, u_self, x, out)


cdef inline double tidy(double angle) noexcept nogil:
    """An angle in (-pi, pi]: within 1e-12 of -pi becomes +pi, -0.0 becomes 0 (``frames.tidy_angle``)."""
    if angle <= -M_PI + 1e-12:
        return M_PI
    return angle + 0.0


cdef void relative(const double* prev, const double* frame, double* T) noexcept nogil:
    """T = prev^-1 frame for rigid poses (R^T)."""
    cdef int i, j
    cdef double w[3]
    for i in range(3):
        w[i] = frame[4 * i + 3] - prev[4 * i + 3]
    for i in range(3):
        for j in range(3):
            T[4 * i + j] = prev[i] * frame[j] + prev[4 + i] * frame[4 + j] + prev[8 + i] * frame[8 + j]
        T[4 * i + 3] = prev[i] * w[0] + prev[4 + i] * w[1] + prev[8 + i] * w[2]
    T[12], T[13], T[14], T[15] = 0.0, 0.0, 0.0, 1.0


cdef void dh_params_c(const double* prev, const double* frame, double* row) noexcept nogil:
    """(a, d, alpha, theta) with prev^-1 frame = Rz(theta) Tz(d) Tx(a) Rx(alpha)."""
    cdef double T[16]
    relative(prev, frame, T)
    cdef double theta = atan2(T[4], T[0])
    cdef double alpha = atan2(T[9], T[10])
    row[0] = T[3] * cos(theta) + T[7] * sin(theta)
    row[1] = T[11]
    row[2] = tidy(alpha)
    row[3] = tidy(theta)


cdef void mdh_params_c(const double* prev, const double* frame, double* row) noexcept nogil:
    """(a, d, alpha, theta) with prev^-1 frame = Rx(alpha) Tx(a) Rz(theta) Tz(d)."""
    cdef double T[16]
    relative(prev, frame, T)
    cdef double alpha = atan2(-T[6], T[10])
    cdef double theta = atan2(-T[1], T[0])
    row[0] = T[3]
    row[1] = -T[7] * sin(alpha) + T[11] * cos(alpha)
    row[2] = tidy(alpha)
    row[3] = tidy(theta)


cdef void dh_matrix_c(const double* row, double* A) noexcept nogil:
    """Rz(theta) Tz(d) Tx(a) Rx(alpha) for row (a, d, alpha, theta)."""
    cdef double ct = cos(row[3]), st = sin(row[3]), ca = cos(row[2]), sa = sin(row[2])
    A[0], A[1], A[2], A[3] = ct, -st * ca, st * sa, row[0] * ct
    A[4], A[5], A[6], A[7] = st, ct * ca, -ct * sa, row[0] * st
    A[8], A[9], A[10], A[11] = 0.0, sa, ca, row[1]
    A[12], A[13], A[14], A[15] = 0.0, 0.0, 0.0, 1.0


cdef double line_distance(const double* p1, const double* u1, const double* p2,
                          const double* u2) noexcept nogil:
    cdef double n[3]
    cdef double w[3]
    cdef double nn, c
    cdef int i
    cross3(u1, u2, n)
    nn = norm3(n)
    for i in range(3):
        w[i] = p2[i] - p1[i]
    if nn < ANGLE_TOL:
        c = dot3(w, u1)
        for i in range(3):
            w[i] = w[i] - c * u1[i]
        return norm3(w)
    return fabs(dot3(w, n)) / nn


cdef void approx_dh_c(const double* prev, const double* target, double* row) noexcept nogil:
    """The conversion paper's last-row rule (``frames.approx_dh_params``), ties to + by KEEP_TOL."""
    cdef double o0[3]
    cdef double x0[3]
    cdef double y0[3]
    cdef double z0[3]
    cdef double o1[3]
    cdef double x1[3]
    cdef double y1[3]
    cdef double z1[3]
    cdef double w[3]
    col(prev, 3, o0)
    col(prev, 0, x0)
    col(prev, 1, y0)
    col(prev, 2, z0)
    col(target, 3, o1)
    col(target, 0, x1)
    col(target, 1, y1)
    col(target, 2, z1)
    cdef int i
    for i in range(3):
        w[i] = o1[i] - o0[i]
    cdef double reach = max(norm3(w), max(norm3(o0), norm3(o1)))
    cdef double theta = atan2(sin_between(x0, x1), dot3(x0, x1))
    if dot3(y0, x1) < -KEEP_TOL:
        theta = -theta
    cdef double alpha = atan2(sin_between(z0, z1), dot3(z0, z1))
    if dot3(y1, z0) < -KEEP_TOL:
        alpha = -alpha
    cdef double d = line_distance(o0, x0, o1, x1)
    if dot3(w, z0) < -KEEP_TOL * reach:
        d = -d
    cdef double a = line_distance(o0, z0, o1, z1)
    if dot3(w, x1) < -KEEP_TOL * reach:
        a = -a
    row[0], row[1], row[2], row[3] = a, d, alpha, theta


cdef inline void line_of(const double* T, double* p, double* u) noexcept nogil:
    """The z axis of a pose as a line: origin p, direction u."""
    col(T, 3, p)
    col(T, 2, u)


cdef void dh_chain(const double* cand, Py_ssize_t n, const double* tool, double scale, bint keep,
                   double* F, double* rows) noexcept nogil:
    """DH frames {0}..{n-1} and the last frame {n} into F (n+1 poses) and the rows (n, 4) between
    them, from the flip-adjusted joint frames ``cand`` (n poses) and the tool pose
    (``representations.dh.dh_frames``)."""
    cdef double I[16]
    cdef double pa[3]
    cdef double ua[3]
    cdef double pb[3]
    cdef double ub[3]
    cdef double row[4]
    cdef double A[16]
    cdef const double* prev = I
    cdef Py_ssize_t i
    tf_identity(I)
    for i in range(n):
        line_of(prev, pa, ua)
        line_of(cand + 16 * i, pb, ub)
        normal_frame_c(pa, ua, pb, ub, True, prev, scale, cand + 16 * i if keep else NULL, F + 16 * i)
        prev = F + 16 * i
    line_of(prev, pa, ua)
    if satisfies(tool, pa, ua, scale, KEEP_TOL):
        tf_copy(tool, F + 16 * n)
    else:
        approx_dh_c(prev, tool, row)
        dh_matrix_c(row, A)
        tf_mul(prev, A, F + 16 * n)
    for i in range(n):
        dh_params_c(F + 16 * i, F + 16 * (i + 1), rows + 4 * i)


cdef void mdh_base(const double* joint1, double scale, double* out) noexcept nogil:
    """Frame {0} of a modified DH table (``representations.mdh._base_frame``): on the base z axis with
    x towards joint 1's axis, or, for a joint 1 axis nearly parallel to that axis, on joint 1's axis
    turned from the base by the smallest rotation taking z onto it."""
    cdef double I[16]
    cdef double zero[3]
    cdef double ez[3]
    cdef double p[3]
    cdef double u[3]
    cdef double w[3]
    cdef double v[3]
    cdef double K[9]
    cdef double ref[16]
    cdef double c, t
    cdef int i, j, k
    tf_identity(I)
    zero[0], zero[1], zero[2] = 0.0, 0.0, 0.0
    ez[0], ez[1], ez[2] = 0.0, 0.0, 1.0
    line_of(joint1, p, u)
    normal_frame_c(zero, ez, p, u, False, I, scale, I, out)
    cdef double s = sin_between(ez, u)
    cdef double r = sqrt(out[3] * out[3] + out[7] * out[7] + out[11] * out[11])
    if not (NOISE_TILT < s and (s < ANGLE_TOL or r > FAR * scale)):
        return
    # an anti-parallel axis is taken as the line along -u, so frame {0}'s z stays near the base z
    for i in range(3):
        w[i] = u[i] if u[2] > 0 else -u[i]
    cross3(ez, w, v)
    c = dot3(ez, w)
    K[0], K[1], K[2] = 0.0, -v[2], v[1]
    K[3], K[4], K[5] = v[2], 0.0, -v[0]
    K[6], K[7], K[8] = -v[1], v[0], 0.0
    t = dot3(p, w)
    for i in range(3):
        for j in range(3):
            ref[4 * i + j] = (1.0 if i == j else 0.0) + K[3 * i + j] + (
                K[3 * i] * K[j] + K[3 * i + 1] * K[3 + j] + K[3 * i + 2] * K[6 + j]) / (1.0 + c)
        ref[4 * i + 3] = p[i] - t * w[i]
    ref[12], ref[13], ref[14], ref[15] = 0.0, 0.0, 0.0, 1.0
    for i in range(3):
        v[i] = ref[4 * i + 3]
    normal_frame_c(v, w, p, u, False, ref, scale, ref, out)


cdef void mdh_chain(const double* cand, Py_ssize_t n, double scale, bint keep,
                    double* M, double* rows) noexcept nogil:
    """Modified DH frames {0}..{n} into M (n+1 poses) and the rows (n, 4) between them, from the
    flip-adjusted joint frames ``cand`` (n poses) (``representations.mdh.mdh_frames``)."""
    cdef double pa[3]
    cdef double ua[3]
    cdef double pb[3]
    cdef double ub[3]
    cdef double x[3]
    cdef double o[3]
    cdef Py_ssize_t i
    mdh_base(cand, scale, M)
    for i in range(n - 1):
        line_of(cand + 16 * i, pa, ua)
        line_of(cand + 16 * (i + 1), pb, ub)
        normal_frame_c(pa, ua, pb, ub, False, M + 16 * i, scale, cand + 16 * i if keep else NULL,
                       M + 16 * (i + 1))
    if keep:
        tf_copy(cand + 16 * (n - 1), M + 16 * n)
    else:
        # frame {n}: where frame {n-1}'s x line meets joint n's axis, with the same x (its x is free)
        line_of(cand + 16 * (n - 1), pa, ua)
        x_line_meet(M + 16 * (n - 1), pa, ua, o)
        col(M + 16 * (n - 1), 0, x)
        from_zx(o, ua, x, M + 16 * n)
    for i in range(n):
        mdh_params_c(M + 16 * i, M + 16 * (i + 1), rows + 4 * i)


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


def robots_fk(L, revolute, Q):
    """Tool poses (B, m, 4, 4) of B robots with n joints each at m configurations each: the robots' own
    compiled FK (``Robot.fk``: the walk of ``fk.pxd``), for the conversions' FK self-check.

    Parameters
    ----------
    L : (B, n + 1, 4, 4) float array
        Each robot's fixed transforms (``robot.local_transforms`` of its frames).
    revolute : (B, n) bool array
    Q : (B, m, n) float array
        Joint values (rad or length units); finite.
    """
    cdef cnp.ndarray La = _f64(L), Qa = _f64(Q)
    cdef cnp.ndarray ra = np.ascontiguousarray(revolute, dtype=np.uint8)
    if La.ndim != 4 or Qa.ndim != 3 or ra.ndim != 2 or La.shape[0] != Qa.shape[0] \
            or ra.shape[0] != Qa.shape[0] or La.shape[1] != Qa.shape[2] + 1 or ra.shape[1] != Qa.shape[2] \
            or La.shape[2] != 4 or La.shape[3] != 4 or Qa.shape[2] < 1:
        raise ValueError("expected L (B, n+1, 4, 4), revolute (B, n) and Q (B, m, n)")
    cdef Py_ssize_t B = Qa.shape[0], m = Qa.shape[1], n = Qa.shape[2], k, c
    out = np.empty((B, m, 4, 4))
    cdef double* l = _ptr(La)
    cdef double* q = _ptr(Qa)
    cdef unsigned char* r = <unsigned char*>cnp.PyArray_DATA(ra)
    cdef double* o = _ptr(out)
    with nogil:
        for k in range(B):
            for c in range(m):
                walk_tool(l + 16 * (n + 1) * k, r + n * k, <int>n, q + n * (m * k + c), o + 16 * (m * k + c))
    return out


cdef void mdh_matrix_c(const double* row, double* A) noexcept nogil:
    """Rx(alpha) Tx(a) Rz(theta) Tz(d) for row (a, d, alpha, theta)."""
    cdef double ct = cos(row[3]), st = sin(row[3]), ca = cos(row[2]), sa = sin(row[2])
    A[0], A[1], A[2], A[3] = ct, -st, 0.0, row[0]
    A[4], A[5], A[6], A[7] = st * ca, ct * ca, -sa, -sa * row[1]
    A[8], A[9], A[10], A[11] = st * sa, ct * sa, ca, ca * row[1]
    A[12], A[13], A[14], A[15] = 0.0, 0.0, 0.0, 1.0


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
