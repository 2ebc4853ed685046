# cython: language_level=3
"""The kinematic chain of a robot as the compiled kernels see it, and the walk along it.

T(q) = L_1 Z_1(q_1) L_2 Z_2(q_2) ... L_n Z_n(q_n) L_{n+1}, with L_1 = J_1, L_i = J_{i-1}^-1 J_i the fixed
transforms between consecutive GJD frames and Z_i a rotation about z (revolute) or a translation along z
(prismatic). This is the product of exponentials exp([S_1] q_1) ... exp([S_n] q_n) M regrouped
(exp([S_i] q) = J_i Z(q) J_i^-1): a joint's motion then mixes two columns of the running pose (revolute)
or adds to its last column (prismatic), instead of a Rodrigues rotation and a 4x4 product per joint.
"""

cimport numpy as cnp
from libc.math cimport sin, cos, isfinite
from robkin.compiled.linalg cimport tf_mul, tf_copy


cdef class Chain:
    cdef readonly int n
    cdef double* L              # (n+1) x 16, row-major 4x4 fixed transforms
    cdef unsigned char* rev     # (n,) 1 = revolute, 0 = prismatic
    cdef object _L_owner        # numpy arrays owning the memory above
    cdef object _rev_owner


cdef inline void move_joint(double* T, bint revolute, double q) noexcept nogil:
    """T <- T Z(q): revolute rotates columns x, y about z; prismatic moves the origin along z."""
    cdef double c, s, x
    cdef int r
    if revolute:
        c = cos(q)
        s = sin(q)
        for r in range(3):
            x = T[4 * r]
            T[4 * r] = c * x + s * T[4 * r + 1]
            T[4 * r + 1] = c * T[4 * r + 1] - s * x
    else:
        for r in range(3):
            T[4 * r + 3] += q * T[4 * r + 2]


cdef inline void walk_tool(const double* L, const unsigned char* rev, int n, const double* q,
                           double* T) noexcept nogil:
    """T = tool pose at q (4x4 row-major)."""
    cdef double A[16]
    cdef double B[16]
    cdef double* cur = A
    cdef double* nxt = B
    cdef double* tmp
    cdef int i
    tf_copy(L, cur)
    for i in range(n - 1):
        move_joint(cur, rev[i], q[i])
        tf_mul(cur, L + 16 * (i + 1), nxt)     # ping-pong between two buffers: no copy per joint
        tmp = cur
        cur = nxt
        nxt = tmp
    move_joint(cur, rev[n - 1], q[n - 1])
    tf_mul(cur, L + 16 * n, T)


cdef inline void walk_frames(const double* L, const unsigned char* rev, int n, const double* q,
                             double* F) noexcept nogil:
    """F[i] (n+1 poses of 16) = frame of joint i after its own motion, F[n] = tool pose."""
    cdef int i
    tf_copy(L, F)
    for i in range(n):
        move_joint(F + 16 * i, rev[i], q[i])
        tf_mul(F + 16 * i, L + 16 * (i + 1), F + 16 * (i + 1))


cdef inline bint usable_q(object q, int n) noexcept:
    """q is a C-contiguous float64 ndarray (n,) or (N, n) with only finite entries (usable as is)."""
    cdef cnp.ndarray a
    cdef Py_ssize_t k, size
    cdef const double* d
    if not cnp.PyArray_Check(q):
        return False
    a = <cnp.ndarray>q
    if cnp.PyArray_TYPE(a) != cnp.NPY_DOUBLE or not cnp.PyArray_IS_C_CONTIGUOUS(a):
        return False
    if cnp.PyArray_NDIM(a) == 1:
        if cnp.PyArray_DIM(a, 0) != n:
            return False
    elif cnp.PyArray_NDIM(a) == 2:
        if cnp.PyArray_DIM(a, 1) != n:
            return False
    else:
        return False
    size = cnp.PyArray_SIZE(a)
    d = <const double*>cnp.PyArray_DATA(a)
    for k in range(size):
        if not isfinite(d[k]):
            return False
    return True


cdef inline cnp.ndarray empty_result(cnp.ndarray q, cnp.npy_intp d0, cnp.npy_intp d1, cnp.npy_intp d2):
    """An uninitialised float64 array of shape q.shape[:-1] + (d0, d1) or + (d0, d1, d2) if d2 > 0:
    one result per configuration of a usable q (n,) or (N, n)."""
    cdef cnp.npy_intp dims[4]
    cdef int lead = cnp.PyArray_NDIM(q) - 1, nd
    if lead:
        dims[0] = cnp.PyArray_DIM(q, 0)
    dims[lead] = d0
    dims[lead + 1] = d1
    dims[lead + 2] = d2
    nd = lead + (3 if d2 > 0 else 2)
    return cnp.PyArray_EMPTY(nd, dims, cnp.NPY_DOUBLE, 0)
