# cython: language_level=3
"""The batch block kernels as a table of function pointers, one table per instruction set.

``kernel_bodies.pxi`` fills a ``BlockKernels`` from the block walks (``fk.walk_block``,
``jacobian_columns.finish_block``, ``dynamics_blocks.pxi``); it is compiled twice, portable
(``kernels.pyx``) and for AVX2 (``kernels_avx2.pyx``), and ``kernels.active_kernels()`` returns the table
chosen for this CPU. Types only: cimporting this file loads no module.
"""

ctypedef void (*pose_block_t)(const double* L, const unsigned char* rev, int n, const double* Q,
                              Py_ssize_t m, Py_ssize_t j, double* T, double* F) noexcept nogil
ctypedef void (*jacobian_block_t)(const double* L, const unsigned char* rev, int n, const double* Q,
                                  Py_ssize_t m, Py_ssize_t j, int kind, double* J, double* T, double* Z,
                                  double* P) noexcept nogil
ctypedef void (*rnea_block_t)(const double* L, const unsigned char* rev, int n, const double* mass,
                              const double* com, const double* inertia, const double* Q, const double* QD,
                              const double* QDD, int m, const double* g, double* S, double* TAU) noexcept nogil
ctypedef void (*crba_block_t)(const double* L, const unsigned char* rev, int n, const double* mass,
                              const double* com, const double* inertia, const double* beyond, const double* Q,
                              int m, double* S, double* M) noexcept nogil

ctypedef struct BlockKernels:
    # block j (BLOCK configurations from BLOCK * j, fewer at the end) of a batch of m: tool poses into
    # T (m x 16) or, F not NULL, the frames into F (m x (n+1) x 16) (``fk.pyx``)
    pose_block_t pose_block
    # block j of a batch's Jacobians (``jacobian.pyx``); Z, P: the calling thread's scratch
    jacobian_block_t jacobian_block
    # one block of m <= BLOCK configurations (``dynamics_blocks.pxi``)
    rnea_block_t rnea_block
    crba_block_t crba_block
