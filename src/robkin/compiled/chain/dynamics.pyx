# cython: language_level=3
"""Rigid-body dynamics of a serial chain: recursive Newton-Euler and the composite-rigid-body mass matrix.

``ChainDynamics`` holds a robot's fixed transforms (the same L as ``fk.Chain``: T(q) = L_1 Z_1(q_1) ...
L_n Z_n(q_n) L_{n+1}) and, per moving body i, its mass, centre of mass and inertia about that centre,
expressed in the body's own frame F_i(q) = L_1 Z_1 ... L_i Z_i (the GJD frame J_i moved to q, whose z
axis is joint i's axis through its origin). Everything is done in body frames with 3-vectors (Craig's
formulation of Luh-Walker-Paul's recursion; Featherstone's CRBA with each composite body's spatial
inertia kept as its first moment and its rotational inertia about the frame's origin, the composite
masses being constants). The walks (``dynamics_blocks.pxi``) take blocks of up to 32
configurations at once, structure-of-arrays, one configuration being a block of one, so a batch and
the single calls agree bit for bit.

The methods validate only what keeps them memory safe: they return ``None`` unless q, qd, qdd are
C-contiguous float64 arrays of one shape (n,) or (N, n) with finite entries; the Python layer
(``robkin.dynamics.rigid_body``) validates and explains.
"""

cimport numpy as cnp
from cython.parallel cimport parallel, prange
from libc.stdlib cimport malloc, free
from robkin.compiled.runtime.threads cimport batch_threads
from robkin.compiled.chain.fk cimport usable_q
from robkin.compiled.runtime.sincos cimport rk_sincos_array, rk_sincos_one
from robkin.compiled.chain.kernel_table cimport BlockKernels
from robkin.compiled.chain.kernels cimport active_kernels

import numpy as np

cnp.import_array()


include "dynamics_blocks.pxi"

cdef enum:
    # blocks of 32 configurations per thread before a batch is split (~3-8 us each at 7 joints: >= ~100
    # us per thread, see fk.pyx), and the blocks a thread takes at a time (dynamic scheduling)
    MIN_BLOCKS_PER_THREAD = 16
    CHUNK_BLOCKS = 2


cdef inline bint same_shape_q(object a, object q, int n) noexcept:
    """a is usable as is (``fk.usable_q``) and has q's shape (q already usable)."""
    if not usable_q(a, n):
        return False
    if cnp.PyArray_NDIM(<cnp.ndarray>a) != cnp.PyArray_NDIM(<cnp.ndarray>q):
        return False
    return cnp.PyArray_DIM(<cnp.ndarray>a, 0) == cnp.PyArray_DIM(<cnp.ndarray>q, 0)


cdef class ChainDynamics:
    """A chain's fixed transforms, joint types and body mass properties, for the dynamics kernels.

    Parameters
    ----------
    L : (n+1, 4, 4) float array
        The fixed transforms of ``fk.Chain``.
    revolute : (n,) bool array
    mass : (n,) float array
        Mass of bodies 1..n (kg).
    com : (n, 3) float array
        Centre of mass of body i in its frame F_i (m).
    inertia : (n, 3, 3) float array
        Inertia of body i about its centre of mass in F_i's axes (kg m^2).
    """

    cdef readonly int n
    cdef object _owners
    cdef const double* L
    cdef const unsigned char* rev
    cdef const double* mass
    cdef const double* com
    cdef const double* inertia
    cdef const double* beyond

    def __cinit__(self, L, revolute, mass, com, inertia):
        cdef cnp.ndarray La = np.ascontiguousarray(L, dtype=np.float64)
        cdef cnp.ndarray ra = np.ascontiguousarray(revolute, dtype=np.uint8)
        cdef cnp.ndarray ma = np.ascontiguousarray(mass, dtype=np.float64)
        cdef cnp.ndarray ca = np.ascontiguousarray(com, dtype=np.float64)
        cdef cnp.ndarray Ia = np.ascontiguousarray(inertia, dtype=np.float64)
        n = ra.shape[0]
        if (n < 1 or La.ndim != 3 or La.shape[0] != n + 1 or La.shape[1] != 4 or La.shape[2] != 4
                or ma.ndim != 1 or ma.shape[0] != n or ca.ndim != 2 or ca.shape[0] != n or ca.shape[1] != 3
                or Ia.ndim != 3 or Ia.shape[0] != n or Ia.shape[1] != 3 or Ia.shape[2] != 3):
            raise ValueError("ChainDynamics: expected L (n+1, 4, 4), revolute (n,), mass (n,), com (n, 3), "
                             "inertia (n, 3, 3)")
        self.n = n
        # mass beyond each body (q-independent): which composite merges happen in the mass matrix
        cdef cnp.ndarray ba = np.ascontiguousarray(np.concatenate([np.cumsum(ma[::-1])[::-1][1:], [0.0]]))
        self._owners = (La, ra, ma, ca, Ia, ba)
        self.beyond = <const double*>cnp.PyArray_DATA(ba)
        self.L = <const double*>cnp.PyArray_DATA(La)
        self.rev = <const unsigned char*>cnp.PyArray_DATA(ra)
        self.mass = <const double*>cnp.PyArray_DATA(ma)
        self.com = <const double*>cnp.PyArray_DATA(ca)
        self.inertia = <const double*>cnp.PyArray_DATA(Ia)

    def inverse_dynamics(self, q, qd, qdd, gravity, int threads=0):
        """Joint torques/forces (n,) or (N, n) for q, qd, qdd of one shape (qd, qdd may be None: zero),
        gravity a float64 array (3,) in the base frame; None if an array is not usable as is.
        ``threads``: 0 automatic (``threads.pyx``), else at most that many; the same bits either way."""
        cdef Py_ssize_t N
        cdef const double* Q
        cdef const double* QD = NULL
        cdef const double* QDD = NULL
        cdef double* O
        cdef double g[3]
        cdef int n = self.n
        if not usable_q(q, n):
            return None
        if qd is not None and not same_shape_q(qd, q, n):
            return None
        if qdd is not None and not same_shape_q(qdd, q, n):
            return None
        if not usable_q(gravity, 3) or cnp.PyArray_NDIM(<cnp.ndarray>gravity) != 1:
            return None
        Q = <const double*>cnp.PyArray_DATA(<cnp.ndarray>gravity)
        g[0] = Q[0]; g[1] = Q[1]; g[2] = Q[2]
        out = cnp.PyArray_EMPTY(cnp.PyArray_NDIM(<cnp.ndarray>q), cnp.PyArray_DIMS(<cnp.ndarray>q), cnp.NPY_DOUBLE, 0)
        Q = <const double*>cnp.PyArray_DATA(q)
        if qd is not None:
            QD = <const double*>cnp.PyArray_DATA(qd)
        if qdd is not None:
            QDD = <const double*>cnp.PyArray_DATA(qdd)
        O = <double*>cnp.PyArray_DATA(out)
        N = cnp.PyArray_SIZE(q) // n
        if self.walk(False, Q, QD, QDD, g, N, O, threads):
            raise MemoryError()
        return out

    def mass_matrix(self, q, int threads=0):
        """Mass matrix (n, n) for q (n,), (N, n, n) for q (N, n); None if q is not usable as is.
        ``threads`` as for ``inverse_dynamics``."""
        cdef Py_ssize_t N
        cdef const double* Q
        cdef double* O
        cdef int n = self.n
        if not usable_q(q, n):
            return None
        cdef cnp.npy_intp dims[3]
        cdef int nd = cnp.PyArray_NDIM(<cnp.ndarray>q)
        dims[0] = cnp.PyArray_DIM(<cnp.ndarray>q, 0)
        dims[nd - 1] = n
        dims[nd] = n
        out = cnp.PyArray_EMPTY(nd + 1, dims, cnp.NPY_DOUBLE, 0)
        Q = <const double*>cnp.PyArray_DATA(q)
        O = <double*>cnp.PyArray_DATA(out)
        N = cnp.PyArray_SIZE(q) // n
        if self.walk(True, Q, NULL, NULL, NULL, N, O, threads):
            raise MemoryError()
        return out

    cdef int walk(self, bint mass_matrix, const double* Q, const double* QD, const double* QDD, const double* g,
                  Py_ssize_t N, double* O, int threads) noexcept:
        """The N configurations Q (N x n) in blocks of up to BLOCK, split over threads: inverse dynamics
        into O (N x n) or, with ``mass_matrix``, mass matrices into O (N x n x n). The number of threads
        that ran out of memory for their scratch (0: all done)."""
        cdef Py_ssize_t j, nb = (N + BLOCK - 1) // BLOCK
        cdef int failed = 0
        cdef int nt = batch_threads(threads, nb, MIN_BLOCKS_PER_THREAD) if nb > 1 else 1
        cdef double* S = NULL
        cdef const BlockKernels* K = active_kernels()   # blocks of more than one: portable or AVX2 build
        if nt <= 1:     # no OpenMP region: entering one costs as much as a single configuration's work
            S = <double*>malloc(sizeof(double) * BLOCK * PER_JOINT * self.n)
            if S == NULL:
                return 1
            with nogil:
                for j in range(nb):
                    self.block(mass_matrix, Q, QD, QDD, g, N, O, j, S, K)
            free(S)
            return 0
        with nogil, parallel(num_threads=nt):
            S = <double*>malloc(sizeof(double) * BLOCK * PER_JOINT * self.n)   # each thread's scratch
            for j in prange(nb, schedule="dynamic", chunksize=CHUNK_BLOCKS):
                if S == NULL:
                    failed += 1   # a reduction: any thread that ran out of memory counts
                    continue
                self.block(mass_matrix, Q, QD, QDD, g, N, O, j, S, K)
            free(S)
        return failed

    cdef inline void block(self, bint mass_matrix, const double* Q, const double* QD, const double* QDD,
                           const double* g, Py_ssize_t N, double* O, Py_ssize_t j, double* S,
                           const BlockKernels* K) noexcept nogil:
        """Block j of ``walk`` with the scratch S (BLOCK * PER_JOINT * n doubles)."""
        cdef Py_ssize_t k = BLOCK * j
        cdef int n = self.n, size = <int>(N - k if N - k < BLOCK else BLOCK)
        if mass_matrix:
            if size == 1:   # a literal block of one: the compiler drops the lane loops' set-up
                crba_block(self.L, self.rev, n, self.mass, self.com, self.inertia, self.beyond, Q + k * n, 1, S,
                           O + k * n * n)
            else:
                K.crba_block(self.L, self.rev, n, self.mass, self.com, self.inertia, self.beyond, Q + k * n, size,
                             S, O + k * n * n)
        elif size == 1:
            rnea_block(self.L, self.rev, n, self.mass, self.com, self.inertia, Q + k * n,
                       QD + k * n if QD != NULL else QD, QDD + k * n if QDD != NULL else QDD, 1, g, S, O + k * n)
        else:
            K.rnea_block(self.L, self.rev, n, self.mass, self.com, self.inertia, Q + k * n,
                         QD + k * n if QD != NULL else QD, QDD + k * n if QDD != NULL else QDD, size, g, S,
                         O + k * n)
