# cython: language_level=3
"""Geometric Jacobians (space, body, and [v; w] at the tool), single configuration and batch.

``jacobian(chain, q, kind)`` returns (6, n) for q (n,) or (N, 6, n) for q (N, n), or ``None`` when q is
not a C-contiguous float64 array of finite values of the right shape (the Python wrapper then validates
and converts). ``kind``: 0 = geometric [v; w] at the tool origin in the base frame, 1 = space (w, v)
(Modern Robotics eq. 5.11), 2 = body (w, v) in the tool frame.
"""

cimport numpy as cnp
from robkin.compiled.fk cimport BLOCK, Chain, empty_result, store_poses, usable_q, walk_block
from libc.stdlib cimport malloc, free
from robkin.compiled.linalg cimport tall_volume

import numpy as np

cnp.import_array()

GEOMETRIC = 0
SPACE = 1
BODY = 2


cdef void jacobian_one(const double* L, const unsigned char* rev, int n, const double* q, int kind,
                       double* J, double* T) noexcept nogil:
    """J (6 x n, row-major) at one configuration q (n,), and the tool pose T (4x4); ``jacobians`` with
    m = 1 (see the module docstring for ``kind``)."""
    jacobians(L, rev, n, q, 1, kind, J, T)


cdef void jacobians(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t m,
                    int kind, double* J, double* T) noexcept nogil:
    """J (m x 6 x n, row-major) at the m configurations Q (m x n); T (4x4) = the last one's tool pose.

    The walk (``fk.walk_block``, blocks of configurations together) parks joint i's axis z_i and a point
    p_i on it (its frame's origin) in column i (p in rows 0-2, z in rows 3-5); once the tool pose is
    known each column is turned into its final form.
    """
    cdef double P[12 * BLOCK]
    cdef Py_ssize_t j, k
    cdef int size, b
    for j in range((m + BLOCK - 1) // BLOCK):
        k = BLOCK * j
        size = <int>(m - k if m - k < BLOCK else BLOCK)
        walk_block(L, rev, n, Q + n * k, size, P, NULL, J + 6 * n * k)
        for b in range(size):
            store_poses(P + b, 1, T, 16)
            finish_columns(rev, n, kind, T, J + 6 * n * (k + b))


cdef inline void finish_columns(const unsigned char* rev, int n, int kind, const double* T,
                                double* J) noexcept nogil:
    """Turn the parked (p_i; z_i) columns of J (6 x n) into Jacobian columns for the tool pose T."""
    cdef double z0, z1, z2, d0, d1, d2, v0, v1, v2, w0, w1, w2
    cdef int i
    for i in range(n):
        z0 = J[3 * n + i]
        z1 = J[4 * n + i]
        z2 = J[5 * n + i]
        if rev[i]:
            w0 = z0
            w1 = z1
            w2 = z2
            if kind == 1:
                # space: v = -z x p = p x z
                d0 = J[i]
                d1 = J[n + i]
                d2 = J[2 * n + i]
                v0 = d1 * z2 - d2 * z1
                v1 = d2 * z0 - d0 * z2
                v2 = d0 * z1 - d1 * z0
            else:
                # geometric and body: v = z x (p_tool - p)
                d0 = T[3] - J[i]
                d1 = T[7] - J[n + i]
                d2 = T[11] - J[2 * n + i]
                v0 = z1 * d2 - z2 * d1
                v1 = z2 * d0 - z0 * d2
                v2 = z0 * d1 - z1 * d0
        else:
            w0 = 0.0
            w1 = 0.0
            w2 = 0.0
            v0 = z0
            v1 = z1
            v2 = z2
        if kind == 2:
            # body: both halves seen from the tool frame, R^T w and R^T v (v = z x (p_tool - p) is
            # the space v minus p_tool x w, as Ad_{T^-1} prescribes)
            d0 = T[0] * w0 + T[4] * w1 + T[8] * w2
            d1 = T[1] * w0 + T[5] * w1 + T[9] * w2
            d2 = T[2] * w0 + T[6] * w1 + T[10] * w2
            w0, w1, w2 = d0, d1, d2
            d0 = T[0] * v0 + T[4] * v1 + T[8] * v2
            d1 = T[1] * v0 + T[5] * v1 + T[9] * v2
            d2 = T[2] * v0 + T[6] * v1 + T[10] * v2
            v0, v1, v2 = d0, d1, d2
        if kind == 0:
            J[i] = v0
            J[n + i] = v1
            J[2 * n + i] = v2
            J[3 * n + i] = w0
            J[4 * n + i] = w1
            J[5 * n + i] = w2
        else:
            J[i] = w0
            J[n + i] = w1
            J[2 * n + i] = w2
            J[3 * n + i] = v0
            J[4 * n + i] = v1
            J[5 * n + i] = v2


def jacobian(Chain chain, q, int kind):
    """(6, n) for q (n,), (N, 6, n) for q (N, n); None if q is not usable as is (see the module doc)."""
    cdef Py_ssize_t N
    cdef int n = chain.n
    cdef const double* Q
    cdef double* O
    cdef double T[16]
    if kind < 0 or kind > 2:
        raise ValueError("kind must be 0 (geometric), 1 (space) or 2 (body)")
    if not usable_q(q, n):
        return None
    out = empty_result(q, 6, n, 0)
    Q = <const double*>cnp.PyArray_DATA(q)
    O = <double*>cnp.PyArray_DATA(out)
    N = cnp.PyArray_SIZE(q) // n
    with nogil:
        jacobians(chain.L, chain.rev, n, Q, N, kind, O, T)
    return out


def volumes(J):
    """Product of the singular values of each matrix of J (..., m, k): (...) array.

    The volume of the image of the unit ball within the span (Yoshikawa's measure for a Jacobian's
    rows), by Householder QR of the tall orientation (backward stable like the SVD; exact zeros stay
    zero).
    """
    cdef cnp.ndarray Ja = np.ascontiguousarray(J, dtype=np.float64)
    if Ja.ndim < 2:
        raise ValueError("volumes: expected (..., m, k)")
    cdef Py_ssize_t m = Ja.shape[Ja.ndim - 2], k = Ja.shape[Ja.ndim - 1]
    cdef Py_ssize_t count = Ja.size // (m * k) if m * k else 0, b, i, j
    cdef bint wide = m < k
    cdef Py_ssize_t rows = k if wide else m, cols = m if wide else k
    lead = np.shape(Ja)
    out = np.empty(lead[:len(lead) - 2])
    cdef double* O = <double*>cnp.PyArray_DATA(out)
    cdef const double* src = <const double*>cnp.PyArray_DATA(Ja)
    cdef const double* A
    cdef double* M = <double*>malloc((m * k if m * k else 1) * sizeof(double))
    if M == NULL:
        raise MemoryError()
    with nogil:
        for b in range(count):
            A = src + b * m * k
            for i in range(m):
                for j in range(k):
                    if wide:
                        M[j * cols + i] = A[i * k + j]     # transpose: rows x cols = k x m
                    else:
                        M[i * k + j] = A[i * k + j]
            O[b] = tall_volume(M, <int>rows, <int>cols) if cols else 1.0
    free(M)
    return out
