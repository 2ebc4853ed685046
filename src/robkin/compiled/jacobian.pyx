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
from robkin.compiled.jacobian_columns cimport finish_block
from robkin.compiled.kernel_table cimport jacobian_block_t
from robkin.compiled.kernels cimport active_kernels
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
    cdef jacobian_block_t jacobian_block
    if m == 1:      # one configuration: (p; z) parked in J itself; literal sizes drop the loops' set-up
        walk_block(L, rev, n, Q, 1, P, NULL, J, 1)
        finish_block(rev, n, kind, P, J, 1, 1, J)
        store_poses(P, 1, T, 16)
        return
    jacobian_block = active_kernels().jacobian_block     # the portable or AVX2 build (kernels.pyx)
    for j in range((m + BLOCK - 1) // BLOCK):
        jacobian_block(L, rev, n, Q, m, j, kind, J, T, Z, P)


cdef int threaded_jacobians(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t m,
                            int kind, double* J, double* T, int threads) noexcept nogil:
    """``jacobians`` with the blocks split over ``threads``, each with its own scratch; -1 if out of
    memory."""
    cdef Py_ssize_t j
    cdef double* Z = NULL     # each thread's own (firstprivate: NULL until it allocates)
    cdef double* P = NULL
    cdef int failed = 0
    cdef jacobian_block_t jacobian_block = active_kernels().jacobian_block
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
