# Included by kernels.pyx (built portable) and kernels_avx2.pyx (built with -mavx2): the batch block
# kernels, from the very same Cython source, put into one BlockKernels table per build. Both builds do
# the same IEEE operations in the same order (setup.py: -ffp-contract=off, no FMA, no -ffast-math), so
# they give the same bits; only the width of the SIMD code the compiler makes of the loops over a
# block's configurations differs (2 doubles a vector with SSE2, 4 with AVX2).

from robkin.compiled.chain.fk cimport BLOCK as POSE_BLOCK, store_poses, walk_block
from robkin.compiled.chain.jacobian_columns cimport finish_block
from robkin.compiled.chain.kernel_table cimport BlockKernels
from robkin.compiled.runtime.sincos cimport rk_sincos_array, rk_sincos_one

include "dynamics_blocks.pxi"


cdef void pose_block(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t m,
                     Py_ssize_t j, double* T, double* F) noexcept nogil:
    """Block j of a batch of m configurations: tool poses into T (m x 16) or, if F is not NULL, the
    frames into F (m x (n+1) x 16)."""
    cdef double P[12 * POSE_BLOCK]
    cdef Py_ssize_t k = POSE_BLOCK * j
    cdef int size = <int>(m - k if m - k < POSE_BLOCK else POSE_BLOCK)
    if F != NULL:
        walk_block(L, rev, n, Q + n * k, size, P, F + 16 * (n + 1) * k, NULL, 0, NULL, 0)
    else:
        walk_block(L, rev, n, Q + n * k, size, P, NULL, NULL, 0, T + 16 * k, 128 * size)
        store_poses(P, size, T + 16 * k, 16)


cdef void jacobian_block(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t m,
                         Py_ssize_t j, int kind, double* J, double* T, double* Z, double* P) noexcept nogil:
    """Block j of a batch's Jacobians J (m x 6 x n) (Z: 6 n x BLOCK, P: 12 x BLOCK doubles of the calling
    thread's scratch); T gets the tool pose of the batch's last configuration when block j holds it."""
    cdef Py_ssize_t k = POSE_BLOCK * j
    cdef int size = <int>(m - k if m - k < POSE_BLOCK else POSE_BLOCK)
    walk_block(L, rev, n, Q + n * k, size, P, NULL, Z, POSE_BLOCK, J + 6 * n * k, 48 * n * size)
    finish_block(rev, n, kind, P, Z, POSE_BLOCK, size, J + 6 * n * k)
    if k + size == m:
        store_poses(P + size - 1, 1, T, 16)


cdef void rnea_kernel(const double* L, const unsigned char* rev, int n, const double* mass, const double* com,
                      const double* inertia, const double* Q, const double* QD, const double* QDD, int m,
                      const double* g, double* S, double* TAU) noexcept nogil:
    """``rnea_block`` (``dynamics_blocks.pxi``) as a function with an address."""
    rnea_block(L, rev, n, mass, com, inertia, Q, QD, QDD, m, g, S, TAU)


cdef void crba_kernel(const double* L, const unsigned char* rev, int n, const double* mass, const double* com,
                      const double* inertia, const double* beyond, const double* Q, int m, double* S,
                      double* M) noexcept nogil:
    """``crba_block`` (``dynamics_blocks.pxi``) as a function with an address."""
    crba_block(L, rev, n, mass, com, inertia, beyond, Q, m, S, M)


cdef BlockKernels TABLE
TABLE.pose_block = pose_block
TABLE.jacobian_block = jacobian_block
TABLE.rnea_block = rnea_kernel
TABLE.crba_block = crba_kernel
