# cython: language_level=3
"""Geometric subproblems of closed-form IK and their bookkeeping, as ``cdef inline`` C functions.

Shared by the closed-form kernels (``closed_form_6r.pyx``, ``closed_form_scara.pyx``); nothing here is
callable from Python. Vectors are ``double[3]``, rotations row-major ``double[9]`` (the conventions and
small helpers of ``linalg.pxd``); points in a plane are complex numbers held as (re, im) pairs.

- ``angle_about``: the angle that turns p onto q about an axis (Paden-Kahan subproblem 1).
- ``two_axes``: two rotations about intersecting axes that carry p onto q (subproblem 2).
- ``cos_sin_equation``: both solutions of A cos x + B sin x = K.
- ``planar_two_link``: both elbows of a planar two-link chain.
- ``wrap_into_limits``, ``wrap_branches``: revolute angles moved by whole turns into their limits,
  nearest a preference, and the validity of each branch.
- ``c_doubles``, ``new_array``: the kernels' inputs as C-contiguous float64 arrays (no copy when they
  already are) and their outputs, without per-call memoryview set-up (single calls stay cheap).

Unit-free tolerances are on cosines (dimensionless); callers verify every assembled solution by an
independent forward kinematics, so a slack here never turns into a wrong answer reported as right.
"""

from libc.math cimport acos, atan2, ceil, cos, fabs, floor, hypot, nearbyint, sin, sqrt
from robkin.compiled.runtime.linalg cimport cross3, dot3, norm3
cimport numpy as cnp

cdef extern from *:
    """
    /* A cosine beyond +-1 by less than this is rounding of a boundary case (a stretched arm, a
       tangent solution) and is clamped; it moves the reached point by ~1e-9 link lengths, well below
       the 1e-9 the caller verifies. Beyond it the case has no real solution. */
    #define RK_COS_SLACK 1e-9
    /* Norms below this (relative to 1: unit vectors, or lengths divided by the robot's size) mean a
       direction is undefined (a point on the rotation axis): the angle is free and the caller's
       preferred value is used. 1e-12 is ~1e4 ulps: rounding of exact coincidences stays below it. */
    #define RK_DEGENERATE 1e-12
    #define RK_TWO_PI 6.283185307179586
    """
    const double COS_SLACK "RK_COS_SLACK"
    const double DEGENERATE "RK_DEGENERATE"
    const double TWO_PI "RK_TWO_PI"


# ------------------------------------------------------------------ closed-form-specific helper
cdef inline void mat3T_mul(const double* A, const double* B, double* out) noexcept nogil:
    """out = A^T B for 3x3 row-major matrices (out must alias neither)."""
    cdef int i, j
    for i in range(3):
        for j in range(3):
            out[3 * i + j] = A[i] * B[j] + A[3 + i] * B[3 + j] + A[6 + i] * B[6 + j]


# ------------------------------------------------------------------------------------ subproblems
cdef inline double angle_about(const double* k, const double* p, const double* q, double free) noexcept nogil:
    """Angle x with Rot(k, x) p = q, where p and q have equal components along the unit axis k.

    Where p (or q) lies on the axis every angle works and ``free`` is returned.
    """
    cdef double pp[3]
    cdef double qq[3]
    cdef double pq[3]
    cdef double kp = dot3(k, p), kq = dot3(k, q)
    cdef int i
    for i in range(3):
        pp[i] = p[i] - k[i] * kp
        qq[i] = q[i] - k[i] * kq
    if norm3(pp) * norm3(qq) < DEGENERATE:
        return free
    cross3(pp, qq, pq)
    return atan2(dot3(k, pq), dot3(pp, qq))


cdef inline bint two_axes(const double* w1, const double* w2, const double* p, const double* q,
                          double free1, double* x1, double* x2) noexcept nogil:
    """Both angle pairs (x1[s], x2[s]) with Rot(w1, x1) Rot(w2, x2) p = q, for unit vectors p, q.

    w1, w2: unit, non-parallel axes through the origin. Returns whether a pair exists. Where the
    intermediate vector lies on w1 (a wrist singularity) x1 is free and ``free1`` is used.
    """
    cdef double w12[3]
    cdef double v[3]
    cdef double b = dot3(w1, w2)
    cross3(w1, w2, w12)
    cdef double denom = b * b - 1.0
    cdef double w2p = dot3(w2, p), w1q = dot3(w1, q)
    cdef double alpha = (b * w2p - w1q) / denom
    cdef double beta = (b * w1q - w2p) / denom
    cdef double g2 = (dot3(p, p) - alpha * alpha - beta * beta - 2.0 * alpha * beta * b) / dot3(w12, w12)
    cdef double gamma = sqrt(g2) if g2 > 0.0 else 0.0
    cdef int s, i
    for s in range(2):
        for i in range(3):
            v[i] = alpha * w1[i] + beta * w2[i] + gamma * w12[i]
        x2[s] = angle_about(w2, p, v, 0.0)
        x1[s] = angle_about(w1, v, q, free1)
        gamma = -gamma
    return g2 >= -COS_SLACK


cdef inline bint cos_sin_equation(double A, double B, double K, double free, double* x) noexcept nogil:
    """Both solutions x[0], x[1] of A cos x + B sin x = K; returns whether they exist.

    Where A = B = 0 the equation holds for every x if K = 0 (``free`` is returned) and for none otherwise.
    """
    cdef double rho = hypot(A, B)
    if rho < DEGENERATE:
        x[0] = free
        x[1] = free
        return fabs(K) < DEGENERATE
    cdef double ratio = K / rho
    cdef double base = atan2(B, A)
    cdef double delta = acos(1.0 if ratio > 1.0 else (-1.0 if ratio < -1.0 else ratio))
    x[0] = base + delta
    x[1] = base - delta
    return fabs(ratio) <= 1.0 + COS_SLACK


cdef struct TwoLink:
    # a planar two-link chain: link vectors a, b as complex numbers, their lengths and relative angle
    double ar, ai, br, bi, la, lb, beta


cdef inline TwoLink two_link(double complex a, double complex b) noexcept:
    """The chain of links a, b (non-zero), with what every solve needs precomputed."""
    cdef TwoLink L
    L.ar, L.ai, L.br, L.bi = a.real, a.imag, b.real, b.imag
    L.la, L.lb = hypot(L.ar, L.ai), hypot(L.br, L.bi)
    L.beta = atan2(L.bi, L.br) - atan2(L.ai, L.ar)
    return L


cdef inline bint planar_two_link(const TwoLink* L, double dr, double di, double free1, double* x1,
                                 double* x2) noexcept nogil:
    """Both elbows (x1[s], x2[s]) of a planar two-link chain; returns whether the target is in reach.

    The chain turns by x1 about the first axis and x2 about the second: the point at first axis + a + b
    when x1 = x2 = 0 goes to first axis + e^{i x1} (a + e^{i x2} b). d is the wanted offset from the
    first axis. Where d = 0 (only if |a| = |b|) x1 is free: ``free1``.
    """
    cdef double la = L.la, lb = L.lb, dd = hypot(dr, di)
    cdef double D = (dd * dd - la * la - lb * lb) / (2.0 * la * lb)
    cdef double delta = acos(1.0 if D > 1.0 else (-1.0 if D < -1.0 else D))
    cdef double scale = la + lb
    cdef double arg_d = atan2(di, dr)
    cdef double c, s, rr, ri
    cdef int k
    for k in range(2):
        x2[k] = -L.beta + (delta if k == 0 else -delta)
        c = cos(x2[k])
        s = sin(x2[k])
        rr = L.ar + c * L.br - s * L.bi                 # a + e^{i x2} b
        ri = L.ai + s * L.br + c * L.bi
        if dd < DEGENERATE * scale or hypot(rr, ri) < DEGENERATE * scale:
            x1[k] = free1
        else:
            x1[k] = arg_d - atan2(ri, rr)
    return fabs(D) <= 1.0 + COS_SLACK


# ---------------------------------------------------------------------------------- bookkeeping
cdef inline bint wrap_into_limits(double* q, const double* ref, const double* lo, const double* hi,
                                  const unsigned char* revolute, Py_ssize_t n, double tol) noexcept nogil:
    """Revolute q[j] moved by whole turns into [lo[j], hi[j]], nearest ref[j]; returns whether every
    joint (prismatic ones only checked) is then within its limits up to ``tol`` (the caller passes
    ``kinematics.limits.LIMIT_TOL``, the one definition of that slack).

    Unlimited revolute joints end up within pi of ref. Where no turn fits, the turn nearest the range
    is taken (and the check fails). A NaN value fails the check.
    """
    cdef Py_ssize_t j
    cdef double k, k_lo, k_hi
    cdef bint ok = True
    for j in range(n):
        if revolute[j] and not (fabs(ref[j] - q[j]) <= TWO_PI * 0.5 and lo[j] - tol - q[j] <= 0.0
                                and hi[j] + tol - q[j] >= 0.0):
            # (skipped where the turn is plainly zero: q within its limits and within pi of ref make
            # k_lo <= 0 <= k_hi and round k to (-)0 below, from the same rounded numbers)
            k_lo = ceil((lo[j] - tol - q[j]) / TWO_PI)             # -inf where unlimited
            k_hi = floor((hi[j] + tol - q[j]) / TWO_PI)            # +inf where unlimited
            k = nearbyint((ref[j] - q[j]) / TWO_PI)                # half to even, as numpy rounds
            if k < k_lo:
                k = k_lo
            if k > k_hi:
                k = k_hi
            q[j] = q[j] + k * TWO_PI
        if not (q[j] >= lo[j] - tol and q[j] <= hi[j] + tol):
            ok = False
    return ok


cdef inline int wrap_branches(double* Q, const unsigned char* geometric, unsigned char* valid,
                              const double* ref, const double* lo, const double* hi,
                              const unsigned char* revolute, Py_ssize_t S, Py_ssize_t n,
                              double tol) noexcept nogil:
    """Every branch row of Q (S, n) wrapped into the limits; valid[s] = geometric[s] and within limits
    (up to ``tol``).

    Returns 0 if some branch is valid, 2 if only limits reject the geometric ones, 1 if none is
    geometric (the caller then says which step failed).
    """
    cdef Py_ssize_t s
    cdef bint any_valid = False, any_geometric = False
    for s in range(S):
        valid[s] = wrap_into_limits(Q + s * n, ref, lo, hi, revolute, n, tol) and geometric[s]
        any_valid |= valid[s]
        any_geometric |= geometric[s]
    return 0 if any_valid else (2 if any_geometric else 1)


cdef inline void read_pose(const double* T, double* R, double* p) noexcept nogil:
    """R (3x3 row-major) and p (3) of the 4x4 row-major pose T."""
    cdef int i, j
    for i in range(3):
        p[i] = T[4 * i + 3]
        for j in range(3):
            R[3 * i + j] = T[4 * i + j]


# --------------------------------------------------------------------------------- array helpers
cdef inline cnp.ndarray c_doubles(object a, int ndim, Py_ssize_t n_last, str name):
    """a as a C-contiguous float64 array (not copied if it is one) of ndim dimensions whose last is
    n_last (and for ndim 3 the middle one too); ValueError naming ``name`` otherwise."""
    cdef cnp.ndarray arr
    if cnp.PyArray_Check(a) and cnp.PyArray_TYPE(<cnp.ndarray>a) == cnp.NPY_DOUBLE \
            and cnp.PyArray_IS_C_CONTIGUOUS(<cnp.ndarray>a):
        arr = <cnp.ndarray>a
    else:
        arr = <cnp.ndarray>cnp.PyArray_FROM_OTF(a, cnp.NPY_DOUBLE,
                                                cnp.NPY_ARRAY_C_CONTIGUOUS | cnp.NPY_ARRAY_ALIGNED)
    if cnp.PyArray_NDIM(arr) != ndim or cnp.PyArray_DIM(arr, ndim - 1) != n_last \
            or (ndim == 3 and cnp.PyArray_DIM(arr, 1) != n_last):
        raise ValueError(f"{name}: expected {ndim} dimensions, the last of size {n_last}, got shape "
                         f"{(<object>arr).shape}")
    return arr


cdef inline cnp.ndarray new_array(int nd, Py_ssize_t d0, Py_ssize_t d1, Py_ssize_t d2, int typenum):
    """An uninitialised C-ordered array of shape (d0,), (d0, d1) or (d0, d1, d2)."""
    cdef cnp.npy_intp dims[3]
    dims[0] = d0
    dims[1] = d1
    dims[2] = d2
    return cnp.PyArray_EMPTY(nd, dims, typenum, 0)
