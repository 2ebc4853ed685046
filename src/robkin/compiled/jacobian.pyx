# cython: language_level=3
"""Geometric Jacobians (space, body, and [v; w] at the tool), single configuration and batch.

``jacobian(chain, q, kind)`` returns (6, n) for q (n,) or (N, 6, n) for q (N, n), or ``None`` when q is
not a C-contiguous float64 array of finite values of the right shape (the Python wrapper then validates
and converts). ``kind``: 0 = geometric [v; w] at the tool origin in the base frame, 1 = space (w, v)
(Modern Robotics eq. 5.11), 2 = body (w, v) in the tool frame.
"""

cimport numpy as cnp
from cython.parallel cimport parallel, prange
from robkin.compiled.fk cimport BLOCK, Chain, empty_result, store_poses, usable_out, usable_q, walk_block
from libc.stdlib cimport malloc, free
from robkin.compiled.linalg cimport tall_volume
from robkin.compiled.threads cimport batch_threads

import numpy as np

cnp.import_array()

GEOMETRIC = 0
SPACE = 1
BODY = 2

cdef enum:
    # blocks of 32 configurations per thread before a batch is split (~3-6 us each at 7 joints: >= ~100
    # us per thread, see fk.pyx), and the blocks a thread takes at a time (dynamic scheduling)
    MIN_BLOCKS_PER_THREAD = 24
    CHUNK_BLOCKS = 2
    # Jacobians per thread before ``volumes`` splits its batch (~0.3 us each), taken 64 at a time
    MIN_VOLUMES_PER_THREAD = 512
    CHUNK_VOLUMES = 64


cdef void jacobian_one(const double* L, const unsigned char* rev, int n, const double* q, int kind,
                       double* J, double* T) noexcept nogil:
    """J (6 x n, row-major) at one configuration q (n,), and the tool pose T (4x4); ``jacobians`` with
    m = 1 (see the module docstring for ``kind``)."""
    jacobians(L, rev, n, q, 1, kind, J, T, NULL)


cdef void jacobians(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t m,
                    int kind, double* J, double* T, double* Z) noexcept nogil:
    """J (m x 6 x n, row-major) at the m configurations Q (m x n); T (4x4) = the last one's tool pose.

    The walk (``fk.walk_block``, blocks of configurations together) parks each joint's origin p_i and
    axis z_i in Z (6 x n x BLOCK doubles of scratch); once the tool poses are known ``finish_block``
    turns them into columns. With m = 1, Z may be NULL: one configuration's (p; z) fit in J itself.
    """
    cdef double P[12 * BLOCK]
    cdef Py_ssize_t j
    if m == 1:      # one configuration: (p; z) parked in J itself; literal sizes drop the loops' set-up
        walk_block(L, rev, n, Q, 1, P, NULL, J, 1)
        finish_block(rev, n, kind, P, J, 1, 1, J)
        store_poses(P, 1, T, 16)
        return
    for j in range((m + BLOCK - 1) // BLOCK):
        jacobian_block(L, rev, n, Q, m, j, kind, J, T, Z, P)


cdef inline void jacobian_block(const double* L, const unsigned char* rev, int n, const double* Q,
                                Py_ssize_t m, Py_ssize_t j, int kind, double* J, double* T, double* Z,
                                double* P) noexcept nogil:
    """Block j of ``jacobians`` (Z, P: this thread's scratch); T gets the tool pose of the batch's last
    configuration when block j holds it."""
    cdef Py_ssize_t k = BLOCK * j
    cdef int size = <int>(m - k if m - k < BLOCK else BLOCK)
    walk_block(L, rev, n, Q + n * k, size, P, NULL, Z, BLOCK)
    finish_block(rev, n, kind, P, Z, BLOCK, size, J + 6 * n * k)
    if k + size == m:
        store_poses(P + size - 1, 1, T, 16)


cdef int threaded_jacobians(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t m,
                            int kind, double* J, double* T, int threads) noexcept nogil:
    """``jacobians`` with the blocks split over ``threads``, each with its own scratch; -1 if out of
    memory."""
    cdef Py_ssize_t j
    cdef double* Z = NULL     # each thread's own (firstprivate: NULL until it allocates)
    cdef double* P = NULL
    cdef int failed = 0
    with parallel(num_threads=threads):
        Z = <double*>malloc((6 * n + 12) * BLOCK * sizeof(double))
        P = Z + 6 * n * BLOCK
        for j in prange((m + BLOCK - 1) // BLOCK, schedule="dynamic", chunksize=CHUNK_BLOCKS):
            if Z != NULL:
                jacobian_block(L, rev, n, Q, m, j, kind, J, T, Z, P)
            else:
                failed += 1   # a reduction: any thread that ran out of memory counts
        free(Z)
    return -1 if failed else 0


cdef inline void finish_block(const unsigned char* rev, int n, int kind, const double* P, const double* Z,
                              int ld, int m, double* J) noexcept nogil:
    """J (m x 6 x n) from the parked p_i, z_i (Z, see ``fk.walk_block``) and the tool poses P of a block.

    Column i of every configuration b of the block is computed in loops over b that vectorise (joint type
    and kind are the same for the whole block), into W, V, then written to J. Z may be J itself when
    m = 1 (a column is read before it is written).
    """
    cdef double W[3 * BLOCK]
    cdef double V[3 * BLOCK]
    cdef double z0, z1, z2, d0, d1, d2
    cdef const double* p0
    cdef const double* p1
    cdef const double* p2
    cdef const double* zi0
    cdef const double* zi1
    cdef const double* zi2
    cdef double* Jb
    cdef int i, b, r, top = 0 if kind == 0 else 3      # the rows of v: [v; w] (geometric), (w, v) otherwise
    for i in range(n):
        p0 = Z + ld * i
        p1 = Z + ld * (n + i)
        p2 = Z + ld * (2 * n + i)
        zi0 = Z + ld * (3 * n + i)
        zi1 = Z + ld * (4 * n + i)
        zi2 = Z + ld * (5 * n + i)
        if not rev[i]:
            # prismatic: no rotation, the axis is the velocity
            for b in range(m):
                W[b] = 0.0
                W[BLOCK + b] = 0.0
                W[2 * BLOCK + b] = 0.0
                V[b] = zi0[b]
                V[BLOCK + b] = zi1[b]
                V[2 * BLOCK + b] = zi2[b]
        elif kind == 1:
            # space: w = z, v = -z x p = p x z
            for b in range(m):
                z0 = zi0[b]
                z1 = zi1[b]
                z2 = zi2[b]
                W[b] = z0
                W[BLOCK + b] = z1
                W[2 * BLOCK + b] = z2
                V[b] = p1[b] * z2 - p2[b] * z1
                V[BLOCK + b] = p2[b] * z0 - p0[b] * z2
                V[2 * BLOCK + b] = p0[b] * z1 - p1[b] * z0
        else:
            # geometric and body: w = z, v = z x (p_tool - p)
            for b in range(m):
                z0 = zi0[b]
                z1 = zi1[b]
                z2 = zi2[b]
                d0 = P[BLOCK * 3 + b] - p0[b]
                d1 = P[BLOCK * 7 + b] - p1[b]
                d2 = P[BLOCK * 11 + b] - p2[b]
                W[b] = z0
                W[BLOCK + b] = z1
                W[2 * BLOCK + b] = z2
                V[b] = z1 * d2 - z2 * d1
                V[BLOCK + b] = z2 * d0 - z0 * d2
                V[2 * BLOCK + b] = z0 * d1 - z1 * d0
        if kind == 2:
            # body: both halves seen from the tool frame, R^T w and R^T v (v = z x (p_tool - p) is
            # the space v minus p_tool x w, as Ad_{T^-1} prescribes)
            rotate_back(P, W, m)
            rotate_back(P, V, m)
        for b in range(m):
            Jb = J + 6 * n * b + i
            for r in range(3):
                Jb[n * (top + r)] = V[BLOCK * r + b]
                Jb[n * (3 - top + r)] = W[BLOCK * r + b]


cdef inline void rotate_back(const double* P, double* X, int m) noexcept nogil:
    """X[:, b] <- R_b^T X[:, b] for the tool rotations R_b of the SoA block P (X: 3 x BLOCK)."""
    cdef double x0, x1, x2
    cdef int b
    for b in range(m):
        x0 = X[b]
        x1 = X[BLOCK + b]
        x2 = X[2 * BLOCK + b]
        X[b] = P[b] * x0 + P[BLOCK * 4 + b] * x1 + P[BLOCK * 8 + b] * x2
        X[BLOCK + b] = P[BLOCK + b] * x0 + P[BLOCK * 5 + b] * x1 + P[BLOCK * 9 + b] * x2
        X[2 * BLOCK + b] = P[BLOCK * 2 + b] * x0 + P[BLOCK * 6 + b] * x1 + P[BLOCK * 10 + b] * x2


def jacobian(Chain chain, q, int kind, int threads=0, out=None):
    """(6, n) for q (n,), (N, 6, n) for q (N, n); None if q (or ``out``) is not usable as is (see the
    module doc). ``threads``: 0 automatic (``threads.pyx``), else at most that many; the same bits
    either way. ``out``: a C-contiguous float64 array of the result's shape to write into."""
    cdef Py_ssize_t N
    cdef int n = chain.n, nt, failed = 0
    cdef const double* Q
    cdef double* O
    cdef double T[16]
    if kind < 0 or kind > 2:
        raise ValueError("kind must be 0 (geometric), 1 (space) or 2 (body)")
    if not usable_q(q, n):
        return None
    if out is None:
        out = empty_result(q, 6, n, 0)
    elif not usable_out(out, q, 6, n, 0):
        return None
    Q = <const double*>cnp.PyArray_DATA(q)
    O = <double*>cnp.PyArray_DATA(out)
    N = cnp.PyArray_SIZE(q) // n
    cdef double* Z = NULL
    nt = batch_threads(threads, (N + BLOCK - 1) // BLOCK, MIN_BLOCKS_PER_THREAD) if N > BLOCK else 1
    if nt > 1:
        with nogil:
            failed = threaded_jacobians(chain.L, chain.rev, n, Q, N, kind, O, T, nt)
        if failed:
            raise MemoryError()
        return out
    if N > 1:
        Z = <double*>malloc(6 * n * BLOCK * sizeof(double))
        if Z == NULL:
            raise MemoryError()
    with nogil:
        jacobians(chain.L, chain.rev, n, Q, N, kind, O, T, Z)
    free(Z)
    return out


def volumes(J, int threads=0):
    """Product of the singular values of each matrix of J (..., m, k): (...) array.

    The volume of the image of the unit ball within the span (Yoshikawa's measure for a Jacobian's
    rows), by Householder QR of the tall orientation (backward stable like the SVD; exact zeros stay
    zero).
    """
    cdef cnp.ndarray Ja = np.ascontiguousarray(J, dtype=np.float64)
    if Ja.ndim < 2:
        raise ValueError("volumes: expected (..., m, k)")
    cdef Py_ssize_t m = Ja.shape[Ja.ndim - 2], k = Ja.shape[Ja.ndim - 1]
    cdef Py_ssize_t count = Ja.size // (m * k) if m * k else 0, b
    cdef bint wide = m < k
    cdef Py_ssize_t rows = k if wide else m, cols = m if wide else k
    lead = np.shape(Ja)
    out = np.empty(lead[:len(lead) - 2])
    cdef double* O = <double*>cnp.PyArray_DATA(out)
    cdef const double* src = <const double*>cnp.PyArray_DATA(Ja)
    cdef int nt = batch_threads(threads, count, MIN_VOLUMES_PER_THREAD), failed = 0
    cdef double* M = NULL     # each thread's own scratch
    with nogil, parallel(num_threads=nt):
        M = <double*>malloc((m * k if m * k else 1) * sizeof(double))
        for b in prange(count, schedule="dynamic", chunksize=CHUNK_VOLUMES):
            if M != NULL:
                O[b] = one_volume(src + b * m * k, M, m, k, wide, rows, cols)
            else:
                failed += 1   # a reduction: any thread that ran out of memory counts
        free(M)
    if failed:
        raise MemoryError()
    return out


cdef inline double one_volume(const double* A, double* M, Py_ssize_t m, Py_ssize_t k, bint wide,
                              Py_ssize_t rows, Py_ssize_t cols) noexcept nogil:
    """The volume of one m x k matrix A, through the scratch M (m * k doubles)."""
    cdef Py_ssize_t i, j
    for i in range(m):
        for j in range(k):
            if wide:
                M[j * cols + i] = A[i * k + j]     # transpose: rows x cols = k x m
            else:
                M[i * k + j] = A[i * k + j]
    return tall_volume(M, <int>rows, <int>cols) if cols else 1.0
