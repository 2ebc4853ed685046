# Line geometry of the frame placement, included by frames.pyx (one extension module: the C functions
# stay static and inlinable, and ``robkin convert`` loads no extra module). Lines are a point p and a
# unit direction u (``double[3]``); poses row-major ``double[16]``. The rules follow ``robkin.lines``
# statement by statement; ANGLE_TOL and LENGTH_TOL are frames.pyx's, read from there.


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


cdef inline void line_of(const double* T, double* p, double* u) noexcept nogil:
    """The z axis of a pose as a line: origin p, direction u."""
    col(T, 3, p)
    col(T, 2, u)
