# cython: language_level=3
"""Forward kinematics and the frames along the chain, single configuration and batch.

``Chain`` holds a robot's fixed transforms once (built by ``Robot``, cached on it); its methods take
joint values and return new numpy arrays. Large batches are split over threads by blocks
(``threads`` = 0: automatic, see ``threads.pyx``); a block is computed the same way on any thread, by
the portable or the AVX2 build of the block kernels (``kernels.pyx``: the CPU's choice, the same bits). They validate nothing beyond what they need to stay memory
safe: they return ``None`` unless q is a C-contiguous float64 array of shape (n,) or (N, n) with only
finite values, and the Python wrapper (``Robot.fk``) then validates and explains.
"""

cimport numpy as cnp
from cython.parallel cimport prange
from robkin.compiled.fk cimport BLOCK, tool_poses, frame_poses, usable_q, empty_result
from robkin.compiled.kernel_table cimport pose_block_t
from robkin.compiled.kernels cimport active_kernels
from robkin.compiled.sincos cimport rk_sincos_array
from robkin.compiled.threads cimport batch_threads

import numpy as np

cnp.import_array()

cdef enum:
    # blocks (of 32 configurations) each thread must get before a batch is split: ~2-4 us of work per
    # block at 7 joints, so >= ~100 us per thread, many times the cost of starting an OpenMP region
    # (~5-20 us) and of a late thread's wake-up on a busy machine
    MIN_BLOCKS_PER_THREAD = 32
    # blocks a thread takes at a time: dynamic scheduling, so a thread that starts late (the machine
    # is busy) takes less of the batch instead of holding the others up at the end
    CHUNK_BLOCKS = 4


cdef void threaded_poses(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t m,
                         double* T, double* F, int threads) noexcept nogil:
    """``tool_poses`` (F NULL) or ``frame_poses`` (T NULL) with the blocks split over ``threads``."""
    cdef Py_ssize_t j
    cdef pose_block_t pose_block = active_kernels().pose_block
    for j in prange((m + BLOCK - 1) // BLOCK, num_threads=threads, schedule="dynamic", chunksize=CHUNK_BLOCKS):
        pose_block(L, rev, n, Q, m, j, T, F)


cdef void batch_poses(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t m,
                      double* T, double* F) noexcept nogil:
    """``threaded_poses`` on this thread; one configuration takes ``fk.pxd``'s inlined walk (a block of
    one fills no SIMD lanes, and the literal size drops the loops' set-up)."""
    cdef Py_ssize_t j
    cdef pose_block_t pose_block
    if m == 1:
        if F != NULL:
            frame_poses(L, rev, n, Q, 1, F)
        else:
            tool_poses(L, rev, n, Q, 1, T)
        return
    pose_block = active_kernels().pose_block
    for j in range((m + BLOCK - 1) // BLOCK):
        pose_block(L, rev, n, Q, m, j, T, F)


cdef class Chain:
    """The fixed transforms L (n+1, 4, 4) and joint types of a robot, for the compiled kernels.

    Parameters
    ----------
    L : (n+1, 4, 4) float array
        T(q) = L_1 Z_1(q_1) ... L_n Z_n(q_n) L_{n+1} (see ``fk.pxd``).
    revolute : (n,) bool array
    """

    def __cinit__(self, L, revolute):
        cdef cnp.ndarray La = np.ascontiguousarray(L, dtype=np.float64)
        cdef cnp.ndarray ra = np.ascontiguousarray(revolute, dtype=np.uint8)
        if La.ndim != 3 or La.shape[1] != 4 or La.shape[2] != 4 or La.shape[0] != ra.shape[0] + 1 \
                or ra.shape[0] < 1:
            raise ValueError("Chain: expected L (n+1, 4, 4) and revolute (n,)")
        self.n = ra.shape[0]
        self._L_owner = La
        self._rev_owner = ra
        self.L = <double*>cnp.PyArray_DATA(La)
        self.rev = <unsigned char*>cnp.PyArray_DATA(ra)

    def fk(self, q, int threads=0, out=None):
        """Tool pose (4, 4) for q (n,), or (N, 4, 4) for q (N, n); None if q (or ``out``) is not usable
        as is. ``threads``: 0 automatic, else at most that many. ``out``: a C-contiguous float64 array of
        the result's shape to write into (returned), else a new one."""
        cdef Py_ssize_t N
        cdef const double* Q
        cdef double* O
        cdef int nt
        if not usable_q(q, self.n):
            return None
        if out is None:
            out = empty_result(q, 4, 4, 0)
        elif not usable_out(out, q, 4, 4, 0):
            return None
        Q = <const double*>cnp.PyArray_DATA(q)
        O = <double*>cnp.PyArray_DATA(out)
        N = cnp.PyArray_SIZE(q) // self.n
        with nogil:
            nt = batch_threads(threads, (N + BLOCK - 1) // BLOCK, MIN_BLOCKS_PER_THREAD) if N > BLOCK else 1
            if nt > 1:
                threaded_poses(self.L, self.rev, self.n, Q, N, O, NULL, nt)
            else:
                batch_poses(self.L, self.rev, self.n, Q, N, O, NULL)
        return out

    def frames(self, q, int threads=0, out=None):
        """Frames after each joint's motion and the tool: (n+1, 4, 4) for q (n,), (N, n+1, 4, 4) for
        q (N, n); None if q (or ``out``) is not usable as is. ``threads`` and ``out`` as for ``fk``."""
        cdef Py_ssize_t N
        cdef const double* Q
        cdef double* O
        cdef int nt
        if not usable_q(q, self.n):
            return None
        if out is None:
            out = empty_result(q, self.n + 1, 4, 4)
        elif not usable_out(out, q, self.n + 1, 4, 4):
            return None
        Q = <const double*>cnp.PyArray_DATA(q)
        O = <double*>cnp.PyArray_DATA(out)
        N = cnp.PyArray_SIZE(q) // self.n
        with nogil:
            nt = batch_threads(threads, (N + BLOCK - 1) // BLOCK, MIN_BLOCKS_PER_THREAD) if N > BLOCK else 1
            if nt > 1:
                threaded_poses(self.L, self.rev, self.n, Q, N, NULL, O, nt)
            else:
                batch_poses(self.L, self.rev, self.n, Q, N, NULL, O)
        return out


def sincos(x):
    """sin and cos of every entry of x, as the kernels compute them (``sincos.h``): (sin, cos) arrays of
    x's shape. Within 1 ulp of glibc's sin and cos; for tests and for anyone who wants the same values."""
    cdef cnp.ndarray xa = np.ascontiguousarray(x, dtype=np.float64)
    cdef cnp.ndarray s = np.empty_like(xa), c = np.empty_like(xa)
    cdef const double* X = <const double*>cnp.PyArray_DATA(xa)
    cdef double* S = <double*>cnp.PyArray_DATA(s)
    cdef double* C = <double*>cnp.PyArray_DATA(c)
    cdef Py_ssize_t j, k, size = xa.size
    with nogil:
        for j in range((size + BLOCK - 1) // BLOCK):
            k = BLOCK * j
            rk_sincos_array(X + k, S + k, C + k, <int>(size - k if size - k < BLOCK else BLOCK))
    return s, c
