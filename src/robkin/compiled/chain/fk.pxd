# cython: language_level=3
"""The kinematic chain of a robot as the compiled kernels see it, and the walk along it.

T(q) = L_1 Z_1(q_1) L_2 Z_2(q_2) ... L_n Z_n(q_n) L_{n+1}, with L_1 = J_1, L_i = J_{i-1}^-1 J_i the fixed
transforms between consecutive GJD frames and Z_i a rotation about z (revolute) or a translation along z
(prismatic). This is the product of exponentials exp([S_1] q_1) ... exp([S_n] q_n) M regrouped
(exp([S_i] q) = J_i Z(q) J_i^-1): a joint's motion then mixes two columns of the running pose (revolute)
or adds to its last column (prismatic), instead of a Rodrigues rotation and a 4x4 product per joint.
Configurations are walked in blocks of up to ``BLOCK`` at once, one configuration being a block of one.
"""

cimport numpy as cnp
from robkin.compiled.runtime.sincos cimport rk_sincos_array, rk_sincos_one

cdef extern from *:
    """
    #include <stdint.h>
    #include <string.h>
    /* 1 if the n doubles at d are all finite. Branch-free over the bits, so that the compiler makes SIMD
       code of it with SSE2 alone (64-bit add, and, or): x is NaN or infinite exactly when its 11 exponent
       bits are all ones, i.e. when (bits & EXP) + 2^52 carries into bit 63. The loop of isfinite() tests
       with an early exit it replaces ran at ~1.4 ns a value (10 ns a 7-joint configuration, before any
       thread started: enough to cap two threads' batch FK at ~1.8x); this one runs at the speed the
       values arrive from memory. */
    static inline int rk_all_finite(const double* d, Py_ssize_t n)
    {
        uint64_t acc = 0, u;
        Py_ssize_t k;
        for (k = 0; k < n; k++) {
            memcpy(&u, d + k, sizeof u);      /* the bits, without breaking strict aliasing */
            acc |= (u & UINT64_C(0x7ff0000000000000)) + UINT64_C(0x0010000000000000);
        }
        return (acc >> 63) == 0;
    }

    /* Part `part` of `parts` of the `bytes` at p asked into the cache for writing (a hint: no effect on
       any value; nothing where the compiler has no prefetch). */
    static inline void rk_prefetch_part(const void* p, Py_ssize_t bytes, int part, int parts)
    {
    #if defined(__GNUC__) || defined(__clang__)
        const char* c = (const char*)p;
        Py_ssize_t o, hi = bytes * (part + 1) / parts;
        for (o = (bytes * part / parts) & ~(Py_ssize_t)63; o < hi; o += 64)
            __builtin_prefetch(c + o, 1, 3);
    #endif
    }
    """
    bint rk_all_finite(const double* d, Py_ssize_t n) noexcept nogil
    void rk_prefetch_part(const void* p, Py_ssize_t bytes, int part, int parts) noexcept nogil


cdef class Chain:
    cdef readonly int n
    cdef double* L              # (n+1) x 16, row-major 4x4 fixed transforms
    cdef unsigned char* rev     # (n,) 1 = revolute, 0 = prismatic
    cdef object _L_owner        # numpy arrays owning the memory above
    cdef object _rev_owner


cdef enum:
    # configurations walked together: a block's arrays (FK: 15 x 32 doubles; Jacobian: 6 n x 32 more
    # and its part of J) stay in L1; measured faster than 16 or 64 for a 7-joint arm
    BLOCK = 32


cdef inline void walk_block(const double* L, const unsigned char* rev, int n, const double* Q, int m,
                            double* P, double* F, double* Z, int ld, const double* ahead,
                            Py_ssize_t ahead_bytes) noexcept nogil:
    """Walk m <= BLOCK configurations Q (m x n, row-major) along the chain together.

    The running poses are kept structure-of-arrays, P[BLOCK * e + b] = entry e (of the 12 of the top three
    rows, row-major) of configuration b, so every step below is a loop over b that the compiler turns into
    SIMD code. On return P holds the tool poses. Per joint: T <- T Z(q) (a revolute joint mixes columns x
    and y with its cos and sin; a prismatic one moves the origin along z), then T <- T L_{i+1}; the
    operations and their order are those of one 4x4 product (``linalg.tf_mul``), whatever m, so a
    configuration gets the same bits in a block of one as in a full block.

    F, if not NULL, receives the frames (m, n+1, 16): frame i after joint i's motion, frame n the tool.
    Z, if not NULL, receives joint i's frame origin p_i and axis z_i after its motion, for the Jacobians:
    Z[ld * (n * r + i) + b] = p_i[r], Z[ld * (n * (r + 3) + i) + b] = z_i[r] (r < 3) with ld >= m.

    ahead, if not NULL: the ``ahead_bytes`` the caller writes after the walk (the block's part of the
    result), asked into the cache a part at each joint, so that the stores that follow do not wait on
    memory one burst at a time (a hint: it changes no value).
    """
    cdef double qb[BLOCK]
    cdef double sb[BLOCK]
    cdef double cb[BLOCK]
    cdef double x, y, c, s, l
    cdef double* row
    cdef double A[12]     # L_{i+1}'s top rows in locals: the compiler cannot know P's stores leave L alone
    cdef int i, b, e, r, w = 16 * (n + 1)
    cdef bint turn
    for e in range(12):
        # through a row pointer: GCC left the fill of P[BLOCK * e + b] scalar (a 32-bit index under
        # -fwrapv may wrap), 12 stores a configuration that cost ~6 % of a batch FK
        row = P + BLOCK * e
        l = L[e]
        for b in range(m):
            row[b] = l
    for i in range(n):
        if ahead != NULL:
            rk_prefetch_part(ahead, ahead_bytes, i, n)
        for b in range(m):
            qb[b] = Q[n * b + i]
        turn = rev[i]
        if turn:
            if m == 1:
                rk_sincos_one(qb[0], sb, cb)       # inline: no call, no loop set-up for one angle
            else:
                rk_sincos_array(qb, sb, cb, m)
        for e in range(12):
            A[e] = L[16 * (i + 1) + e]
        if turn and F == NULL:
            # the rotation and L_{i+1} in one pass over P (half the loads and stores of two); a rotation
            # about z leaves columns z and p as they were, so they are parked for the Jacobians first
            if Z != NULL:
                for r in range(3):
                    copy_row(P + BLOCK * (4 * r + 3), Z + ld * (n * r + i), m)
                    copy_row(P + BLOCK * (4 * r + 2), Z + ld * (n * (r + 3) + i), m)
            for b in range(m):
                c = cb[b]
                s = sb[b]
                for r in range(3):
                    x = P[BLOCK * (4 * r) + b]
                    y = P[BLOCK * (4 * r + 1) + b]
                    times_link(P + BLOCK * 4 * r + b, A, c * x + s * y, c * y - s * x,
                               P[BLOCK * (4 * r + 2) + b], P[BLOCK * (4 * r + 3) + b])
            continue
        if turn:
            for b in range(m):
                c = cb[b]
                s = sb[b]
                for r in range(3):
                    x = P[BLOCK * (4 * r) + b]
                    P[BLOCK * (4 * r) + b] = c * x + s * P[BLOCK * (4 * r + 1) + b]
                    P[BLOCK * (4 * r + 1) + b] = c * P[BLOCK * (4 * r + 1) + b] - s * x
        else:
            for b in range(m):
                for r in range(3):
                    P[BLOCK * (4 * r + 3) + b] += qb[b] * P[BLOCK * (4 * r + 2) + b]
        if F != NULL:
            store_poses(P, m, F + 16 * i, w)
        if Z != NULL:
            for r in range(3):
                copy_row(P + BLOCK * (4 * r + 3), Z + ld * (n * r + i), m)
                copy_row(P + BLOCK * (4 * r + 2), Z + ld * (n * (r + 3) + i), m)
        for b in range(m):
            for r in range(3):
                times_link(P + BLOCK * 4 * r + b, A, P[BLOCK * (4 * r) + b], P[BLOCK * (4 * r + 1) + b],
                           P[BLOCK * (4 * r + 2) + b], P[BLOCK * (4 * r + 3) + b])
    if F != NULL:
        store_poses(P, m, F + 16 * n, w)


cdef inline void times_link(double* row, const double* A, double a0, double a1, double a2,
                            double a3) noexcept nogil:
    """One row (a0 a1 a2 a3) of a block's running poses times L_{i+1} (its top rows A, row-major), into
    row[0], row[BLOCK], row[2 BLOCK], row[3 BLOCK] (the row's entries in the SoA block): the operations and
    order of ``linalg.tf_mul``."""
    row[0] = a0 * A[0] + a1 * A[4] + a2 * A[8]
    row[BLOCK] = a0 * A[1] + a1 * A[5] + a2 * A[9]
    row[2 * BLOCK] = a0 * A[2] + a1 * A[6] + a2 * A[10]
    row[3 * BLOCK] = a0 * A[3] + a1 * A[7] + a2 * A[11] + a3


cdef inline void copy_row(const double* src, double* dst, int m) noexcept nogil:
    """dst[:m] = src[:m] (one loop per row: the compiler vectorises it after one overlap check)."""
    cdef int b
    for b in range(m):
        dst[b] = src[b]


cdef inline void store_poses(const double* P, int m, double* T, int stride) noexcept nogil:
    """T[stride * b : stride * b + 16] = pose b (4x4 row-major, last row 0 0 0 1) of the SoA block P."""
    cdef int b, e
    cdef double* Tb
    for b in range(m):
        Tb = T + stride * b
        for e in range(12):
            Tb[e] = P[BLOCK * e + b]
        Tb[12] = 0.0
        Tb[13] = 0.0
        Tb[14] = 0.0
        Tb[15] = 1.0


cdef inline void tool_poses(const double* L, const unsigned char* rev, int n, const double* Q,
                            Py_ssize_t m, double* T) noexcept nogil:
    """T (m x 16) = tool poses (4x4 row-major) at the m configurations Q (m x n), any m >= 0."""
    cdef double P[12 * BLOCK]
    cdef Py_ssize_t j, k
    cdef int size
    if m == 1:      # a literal block size of one lets the compiler drop the loops' set-up
        walk_block(L, rev, n, Q, 1, P, NULL, NULL, 0, NULL, 0)
        store_poses(P, 1, T, 16)
        return
    for j in range((m + BLOCK - 1) // BLOCK):
        k = BLOCK * j
        size = <int>(m - k if m - k < BLOCK else BLOCK)
        walk_block(L, rev, n, Q + n * k, size, P, NULL, NULL, 0, NULL, 0)
        store_poses(P, size, T + 16 * k, 16)


cdef inline void frame_poses(const double* L, const unsigned char* rev, int n, const double* Q,
                             Py_ssize_t m, double* F) noexcept nogil:
    """F (m x (n+1) x 16) = the frames along the chain (see ``walk_block``) at Q (m x n), any m >= 0."""
    cdef double P[12 * BLOCK]
    cdef Py_ssize_t j, k
    for j in range((m + BLOCK - 1) // BLOCK):
        k = BLOCK * j
        walk_block(L, rev, n, Q + n * k, <int>(m - k if m - k < BLOCK else BLOCK), P, F + 16 * (n + 1) * k,
                   NULL, 0, NULL, 0)


cdef inline void walk_tool(const double* L, const unsigned char* rev, int n, const double* q,
                           double* T) noexcept nogil:
    """T = tool pose (4x4 row-major) at one configuration q (n,): ``tool_poses`` with m = 1."""
    tool_poses(L, rev, n, q, 1, T)


cdef inline bint usable_layout(object q, int n) noexcept:
    """q is a C-contiguous float64 ndarray (n,) or (N, n); its values are not looked at (the batch
    kernels check each block's values on the thread that walks it: ``finite_block``)."""
    cdef cnp.ndarray a
    if not cnp.PyArray_Check(q):
        return False
    a = <cnp.ndarray>q
    if cnp.PyArray_TYPE(a) != cnp.NPY_DOUBLE or not cnp.PyArray_IS_C_CONTIGUOUS(a):
        return False
    if cnp.PyArray_NDIM(a) == 1:
        return cnp.PyArray_DIM(a, 0) == n
    if cnp.PyArray_NDIM(a) == 2:
        return cnp.PyArray_DIM(a, 1) == n
    return False


cdef inline bint usable_q(object q, int n) noexcept:
    """q is a C-contiguous float64 ndarray (n,) or (N, n) with only finite entries (usable as is)."""
    if not usable_layout(q, n):
        return False
    return rk_all_finite(<const double*>cnp.PyArray_DATA(<cnp.ndarray>q), cnp.PyArray_SIZE(<cnp.ndarray>q))


cdef inline bint finite_block(const double* Q, int n, Py_ssize_t m, Py_ssize_t j) noexcept nogil:
    """Block j (``BLOCK`` configurations from BLOCK * j, fewer at the end) of a batch Q (m x n) holds
    only finite values. The batch kernels test each block on the thread that then walks it, while its
    values are in that core's cache: a scan of the whole batch before the threads start would be a
    serial share (~3.4 ns a 7-joint configuration, 5-10 % of a threaded FK on two cores, far more on
    many)."""
    cdef Py_ssize_t k = BLOCK * j
    return rk_all_finite(Q + n * k, n * (m - k if m - k < BLOCK else BLOCK))


cdef inline bint usable_out(object out, cnp.ndarray q, cnp.npy_intp d0, cnp.npy_intp d1,
                            cnp.npy_intp d2) noexcept:
    """out is a writeable C-contiguous float64 ndarray of the shape ``empty_result`` would make."""
    cdef cnp.ndarray a
    cdef int lead = cnp.PyArray_NDIM(q) - 1, nd = lead + (3 if d2 > 0 else 2)
    if not cnp.PyArray_Check(out):
        return False
    a = <cnp.ndarray>out
    if (cnp.PyArray_TYPE(a) != cnp.NPY_DOUBLE or not cnp.PyArray_IS_C_CONTIGUOUS(a)
            or not cnp.PyArray_ISWRITEABLE(a) or cnp.PyArray_NDIM(a) != nd):
        return False
    if lead and cnp.PyArray_DIM(a, 0) != cnp.PyArray_DIM(q, 0):
        return False
    if cnp.PyArray_DIM(a, lead) != d0 or cnp.PyArray_DIM(a, lead + 1) != d1:
        return False
    return d2 <= 0 or cnp.PyArray_DIM(a, lead + 2) == d2


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
