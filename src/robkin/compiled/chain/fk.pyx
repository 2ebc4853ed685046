# cython: language_level=3
"""Forward kinematics and the frames along the chain, single configuration and batch.

``Chain`` holds a robot's fixed transforms once (built by ``Robot``, cached on it); its methods take
joint values and return new numpy arrays. Large batches are split over threads by blocks
(``threads`` = 0: automatic, see ``threads.pyx``); a block is computed the same way on any thread, by
the portable or the AVX2 build of the block kernels (``kernels.pyx``: the CPU's choice, the same bits).
They validate nothing beyond what they need to stay memory safe: they return ``None`` unless q is a
C-contiguous float64 array of shape (n,) or (N, n) with only finite values, and the Python wrapper
(``Robot.fk``) then validates and explains. The values are checked block by block, by the thread that
walks the block (no serial pass over the batch): when one is not finite, ``out`` may already hold some
of the results.

Threads take the blocks in a guided schedule: the first thread a contiguous half of them, the next a
half of the rest, and so on down to ``CHUNK_BLOCKS``. Each thread thus writes (and, for a fresh result,
first touches: the page faults that zero new memory) its own long stretch of the output, instead of
two threads faulting on the same 2 MB huge page in turn; a thread that starts late (a busy machine)
still finds work left, and none waits long at the end.
"""

cimport numpy as cnp
from cython.parallel cimport prange
from robkin.compiled.chain.fk cimport BLOCK, finite_block, tool_poses, frame_poses, usable_layout, empty_result
from robkin.compiled.chain.kernel_table cimport pose_block_t
from robkin.compiled.chain.kernels cimport active_kernels
from robkin.compiled.runtime.sincos cimport rk_sincos_array
from robkin.compiled.runtime.threads cimport batch_threads

import numpy as np

cnp.import_array()

cdef enum:
    # blocks (of 32 configurations) each thread must get before a batch is split: ~2-4 us of work per
    # block at 7 joints, so >= ~100 us per thread, many times the cost of starting an OpenMP region
    # (~5-20 us) and of a late thread's wake-up on a busy machine
    MIN_BLOCKS_PER_THREAD = 32
    # the smallest share of blocks a thread takes at a time (guided schedule, see the module doc)
    CHUNK_BLOCKS = 4


cdef Py_ssize_t threaded_poses(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t m,
                               double* T, double* F, int threads) noexcept nogil:
    """``tool_poses`` (F NULL) or ``frame_poses`` (T NULL) with the blocks split over ``threads``; returns
    the number of blocks left unwritten because a value in them is not finite (0: all written)."""
    cdef Py_ssize_t j, bad = 0
    cdef pose_block_t pose_block = active_kernels().pose_block
    for j in prange((m + BLOCK - 1) // BLOCK, num_threads=threads, schedule="guided", chunksize=CHUNK_BLOCKS):
        if finite_block(Q, n, m, j):
            pose_block(L, rev, n, Q, m, j, T, F)
        else:
            bad += 1
    return bad


cdef Py_ssize_t batch_poses(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t m,
                            double* T, double* F) noexcept nogil:
    """``threaded_poses`` on this thread (no OpenMP region: entering one costs more than a small batch);
    one configuration takes ``fk.pxd``'s inlined walk (a block of one fills no SIMD lanes, and the
    literal size drops the loops' set-up)."""
    cdef Py_ssize_t j
    cdef pose_block_t pose_block
    if m == 1:
        if not finite_block(Q, n, 1, 0):
            return 1
        if F != NULL:
            frame_poses(L, rev, n, Q, 1, F)
        else:
            tool_poses(L, rev, n, Q, 1, T)
        return 0
    pose_block = active_kernels().pose_block
    for j in range((m + BLOCK - 1) // BLOCK):
        if not finite_block(Q, n, m, j):
            return 1
        pose_block(L, rev, n, Q, m, j, T, F)
    return 0


cdef object poses(Chain chain, q, int threads, out, cnp.npy_intp d0, cnp.npy_intp d1, cnp.npy_intp d2, bint frames):
    """``Chain.fk`` (``frames`` false: results d0 x d1 = 4 x 4) or ``Chain.frames`` (n+1 x 4 x 4)."""
    cdef Py_ssize_t N, bad
    cdef const double* Q
    cdef double* O
    cdef int nt, n = chain.n
    if not usable_layout(q, n):
        return None
    if out is None:
        out = empty_result(q, d0, d1, d2)
    elif not usable_out(out, q, d0, d1, d2):
        return None
    Q = <const double*>cnp.PyArray_DATA(q)
    O = <double*>cnp.PyArray_DATA(out)
    N = cnp.PyArray_SIZE(q) // n
    with nogil:
        nt = batch_threads(threads, (N + BLOCK - 1) // BLOCK, MIN_BLOCKS_PER_THREAD) if N > BLOCK else 1
        if nt > 1:
            bad = threaded_poses(chain.L, chain.rev, n, Q, N, NULL if frames else O, O if frames else NULL, nt)
        else:
            bad = batch_poses(chain.L, chain.rev, n, Q, N, NULL if frames else O, O if frames else NULL)
    return None if bad else out


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
        return poses(self, q, threads, out, 4, 4, 0, False)

    def frames(self, q, int threads=0, out=None):
        """Frames after each joint's motion and the tool: (n+1, 4, 4) for q (n,), (N, n+1, 4, 4) for
        q (N, n); None if q (or ``out``) is not usable as is. ``threads`` and ``out`` as for ``fk``."""
        return poses(self, q, threads, out, self.n + 1, 4, 4, True)


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
