# cython: language_level=3
"""Geometric Jacobians (space, body, and [v; w] at the tool), single configuration and batch.

``jacobian(chain, q, kind)`` returns (6, n) for q (n,) or (N, 6, n) for q (N, n), or ``None`` when q is
not a C-contiguous float64 array of finite values of the right shape (the Python wrapper then validates
and converts). ``kind``: 0 = geometric [v; w] at the tool origin in the base frame, 1 = space (w, v)
(Modern Robotics eq. 5.11), 2 = body (w, v) in the tool frame.
"""

cimport numpy as cnp
from cython.parallel cimport parallel, prange
from robkin.compiled.chain.fk cimport (BLOCK, Chain, empty_result, finite_block, store_poses, usable_layout, usable_out,
                                 walk_block)
from robkin.compiled.chain.jacobian_columns cimport finish_block
from robkin.compiled.chain.kernel_table cimport jacobian_block_t
from robkin.compiled.chain.kernels cimport active_kernels
from libc.stdlib cimport malloc, free
from robkin.compiled.runtime.linalg cimport tall_volume
from robkin.compiled.runtime.threads cimport batch_threads

import numpy as np

cnp.import_array()

GEOMETRIC = 0
SPACE = 1
BODY = 2

cdef enum:
    # blocks of 32 configurations per thread before a batch is split (~3-6 us each at 7 joints: >= ~100
    # us per thread, see fk.pyx), and the fewest blocks a thread takes at a time (guided schedule, as
    # in fk.pyx: each thread writes and first-touches its own long stretch of J)
    MIN_BLOCKS_PER_THREAD = 24
    CHUNK_BLOCKS = 2
    # Jacobians per thread before ``volumes`` splits its batch (~0.3 us each), taken 64 at a time
    MIN_VOLUMES_PER_THREAD = 512
    CHUNK_VOLUMES = 64
    # manipulability: blocks per thread before a batch is split (a block's Jacobians and their volumes,
    # ~10-15 us at 7 joints) and the fewest a thread takes at a time (guided)
    MIN_MANIPULABILITY_BLOCKS = 12
    CHUNK_MANIPULABILITY = 2


cdef void jacobian_one(const double* L, const unsigned char* rev, int n, const double* q, int kind,
                       double* J, double* T) noexcept nogil:
    """J (6 x n, row-major) at one configuration q (n,), and the tool pose T (4x4); ``jacobians`` with
    m = 1 (see the module docstring for ``kind``)."""
    jacobians(L, rev, n, q, 1, kind, J, T, NULL)


cdef Py_ssize_t jacobians(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t m,
                          int kind, double* J, double* T, double* Z) noexcept nogil:
    """J (m x 6 x n, row-major) at the m configurations Q (m x n); T (4x4) = the last one's tool pose.
    Returns 0, or 1 when a block holds a value that is not finite (the rest of J is then not written).

    The walk (``fk.walk_block``, blocks of configurations together) parks each joint's origin p_i and
    axis z_i in Z (6 x n x BLOCK doubles of scratch); once the tool poses are known ``finish_block``
    turns them into columns. With m = 1, Z may be NULL: one configuration's (p; z) fit in J itself
    (and its values are not checked: ``jacobian_one``'s callers have).
    """
    cdef double P[12 * BLOCK]
    cdef Py_ssize_t j
    cdef jacobian_block_t jacobian_block
    if m == 1:      # one configuration: (p; z) parked in J itself; literal sizes drop the loops' set-up
        walk_block(L, rev, n, Q, 1, P, NULL, J, 1, NULL, 0)
        finish_block(rev, n, kind, P, J, 1, 1, J)
        store_poses(P, 1, T, 16)
        return 0
    jacobian_block = active_kernels().jacobian_block     # the portable or AVX2 build (kernels.pyx)
    for j in range((m + BLOCK - 1) // BLOCK):
        if not finite_block(Q, n, m, j):
            return 1
        jacobian_block(L, rev, n, Q, m, j, kind, J, T, Z, P)
    return 0


cdef Py_ssize_t threaded_jacobians(const double* L, const unsigned char* rev, int n, const double* Q,
                                   Py_ssize_t m, int kind, double* J, double* T, int threads) noexcept nogil:
    """``jacobians`` with the blocks split over ``threads``, each with its own scratch; -1 if out of
    memory, else the number of blocks holding a value that is not finite (left unwritten)."""
    cdef Py_ssize_t j, bad = 0
    cdef double* Z = NULL     # each thread's own (firstprivate: NULL until it allocates)
    cdef double* P = NULL
    cdef int failed = 0
    cdef jacobian_block_t jacobian_block = active_kernels().jacobian_block
    with parallel(num_threads=threads):
        Z = <double*>malloc((6 * n + 12) * BLOCK * sizeof(double))
        P = Z + 6 * n * BLOCK
        for j in prange((m + BLOCK - 1) // BLOCK, schedule="guided", chunksize=CHUNK_BLOCKS):
            if Z == NULL:
                failed += 1   # a reduction: any thread that ran out of memory counts
            elif finite_block(Q, n, m, j):
                jacobian_block(L, rev, n, Q, m, j, kind, J, T, Z, P)
            else:
                bad += 1
        free(Z)
    return -1 if failed else bad


def jacobian(Chain chain, q, int kind, int threads=0, out=None):
    """(6, n) for q (n,), (N, 6, n) for q (N, n); None if q (or ``out``) is not usable as is (see the
    module doc; a value that is not finite is found block by block, so ``out`` may then hold some
    results). ``threads``: 0 automatic (``threads.pyx``), else at most that many; the same bits either
    way. ``out``: a C-contiguous float64 array of the result's shape to write into."""
    cdef Py_ssize_t N, bad
    cdef int n = chain.n, nt
    cdef const double* Q
    cdef double* O
    cdef double T[16]
    if kind < 0 or kind > 2:
        raise ValueError("kind must be 0 (geometric), 1 (space) or 2 (body)")
    if not usable_layout(q, n):
        return None
    N = cnp.PyArray_SIZE(q) // n
    if N == 1 and not finite_block(<const double*>cnp.PyArray_DATA(q), n, 1, 0):
        return None
    if out is None:
        out = empty_result(q, 6, n, 0)
    elif not usable_out(out, q, 6, n, 0):
        return None
    Q = <const double*>cnp.PyArray_DATA(q)
    O = <double*>cnp.PyArray_DATA(out)
    cdef double* Z = NULL
    nt = batch_threads(threads, (N + BLOCK - 1) // BLOCK, MIN_BLOCKS_PER_THREAD) if N > BLOCK else 1
    if nt > 1:
        with nogil:
            bad = threaded_jacobians(chain.L, chain.rev, n, Q, N, kind, O, T, nt)
        if bad < 0:
            raise MemoryError()
        return None if bad else out
    if N > 1:
        Z = <double*>malloc(6 * n * BLOCK * sizeof(double))
        if Z == NULL:
            raise MemoryError()
    with nogil:
        bad = jacobians(chain.L, chain.rev, n, Q, N, kind, O, T, Z)
    free(Z)
    return None if bad else out


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


cdef inline bint measure_block(jacobian_block_t jacobian_block, const double* L, const unsigned char* rev, int n,
                               const double* Q, Py_ssize_t m, Py_ssize_t j, int first, int rows, double* V,
                               double* S) noexcept nogil:
    """V[k:k + size] for block j (k = BLOCK j) of ``manipulability_blocks``, through the scratch S
    (``SCRATCH`` doubles); False, with nothing written, when a value of the block is not finite."""
    cdef Py_ssize_t k = BLOCK * j
    cdef int b, size = <int>(m - k if m - k < BLOCK else BLOCK)
    cdef bint wide = rows < n
    if not finite_block(Q, n, m, j):
        return False
    # the block as a batch of its own (block 0 of ``size``): J (BLOCK x 6 x n) at S, then Z (6 n x BLOCK),
    # P (12 x BLOCK), the volume's scratch M (rows x n) and the last tool pose (16)
    jacobian_block(L, rev, n, Q + n * k, size, 0, 0, S, S + (12 * n + 12) * BLOCK + rows * n,
                   S + 6 * n * BLOCK, S + 12 * n * BLOCK)
    for b in range(size):
        V[k + b] = one_volume(S + 6 * n * b + n * first, S + (12 * n + 12) * BLOCK, rows, n, wide,
                              n if wide else rows, rows if wide else n)
    return True


cdef Py_ssize_t manipulability_blocks(const double* L, const unsigned char* rev, int n, const double* Q,
                                      Py_ssize_t m, int first, int rows, double* V, int threads) noexcept nogil:
    """V[b] = the volume of rows ``first`` .. ``first + rows - 1`` of the geometric Jacobian at Q[b]
    (m x n), block by block over ``threads`` (one: no OpenMP region): each thread walks a block into its
    own scratch (the block's Jacobians, the walk's Z and P) and takes the volumes there, so the memory is
    V and ~30 kB a thread whatever m. Returns -1 if out of memory, else the number of blocks holding a
    value that is not finite (left unwritten)."""
    cdef Py_ssize_t j, bad = 0
    cdef Py_ssize_t blocks = (m + BLOCK - 1) // BLOCK
    cdef size_t scratch = ((12 * n + 12) * BLOCK + rows * n + 16) * sizeof(double)
    cdef int failed = 0
    cdef double* S = NULL     # each thread's own (firstprivate: NULL until it allocates)
    cdef jacobian_block_t jacobian_block = active_kernels().jacobian_block
    if threads <= 1:
        S = <double*>malloc(scratch)
        if S == NULL:
            return -1
        for j in range(blocks):
            if not measure_block(jacobian_block, L, rev, n, Q, m, j, first, rows, V, S):
                bad = 1
                break
        free(S)
        return bad
    with parallel(num_threads=threads):
        S = <double*>malloc(scratch)
        for j in prange(blocks, schedule="guided", chunksize=CHUNK_MANIPULABILITY):
            if S == NULL:
                failed += 1   # a reduction: any thread that ran out of memory counts
            elif not measure_block(jacobian_block, L, rev, n, Q, m, j, first, rows, V, S):
                bad += 1
        free(S)
    return -1 if failed else bad


def manipulability(Chain chain, q, int first, int rows, int threads=0):
    """Yoshikawa's measure of rows ``first`` .. ``first + rows - 1`` of the geometric Jacobian [v; w]:
    a 0-d array for q (n,), (N,) for q (N, n); None if q is not usable as is (see the module doc).

    The same bits as ``volumes(jacobian(chain, q, 0)[..., first:first + rows, :])``, without the N x 6 x n
    Jacobians: blocks of configurations are walked and measured in per-thread scratch. ``threads`` as
    for ``jacobian``.
    """
    cdef Py_ssize_t N, bad
    cdef int n = chain.n, nt
    if first < 0 or rows < 1 or first + rows > 6:
        raise ValueError("manipulability: rows first .. first + rows - 1 must lie within 0 .. 5")
    if not usable_layout(q, n):
        return None
    N = cnp.PyArray_SIZE(q) // n
    cdef cnp.ndarray out = np.empty(() if cnp.PyArray_NDIM(<cnp.ndarray>q) == 1 else (N,))
    cdef const double* Q = <const double*>cnp.PyArray_DATA(q)
    cdef double* V = <double*>cnp.PyArray_DATA(out)
    nt = batch_threads(threads, (N + BLOCK - 1) // BLOCK, MIN_MANIPULABILITY_BLOCKS) if N > BLOCK else 1
    with nogil:
        bad = manipulability_blocks(chain.L, chain.rev, n, Q, N, first, rows, V, nt)
    if bad < 0:
        raise MemoryError()
    return None if bad else out


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
