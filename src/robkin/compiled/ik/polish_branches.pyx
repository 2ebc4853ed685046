"""Newton polish of closed-form branches on a 6-joint chain's exact forward kinematics, in place.

The branches of an arm within calibration error of a closed-form class are solved on the ideal arm
(``kinematics.near_class``) and then pulled onto the real arm here, target by target, over threads.
"""

import numpy as np

cimport numpy as cnp
from cython.parallel cimport prange
from robkin.compiled.chain.fk cimport Chain
from robkin.compiled.ik.newton cimport CANDIDATE_TOL, newton_polish
from robkin.compiled.runtime.threads cimport batch_threads

cnp.import_array()


cdef inline void polish_target(const double* L, const unsigned char* rev, double scale, const double* t,
                               double* q, unsigned char* v, Py_ssize_t S) noexcept nogil:
    """The S branches q (S, 6) of one target t (4x4) polished in place; v (S,) cleared where they fail."""
    cdef double Rd[9]
    cdef double pd[3]
    cdef double w[6]
    cdef Py_ssize_t s, i, j
    for i in range(3):
        pd[i] = t[4 * i + 3]
        for j in range(3):
            Rd[3 * i + j] = t[4 * i + j]
    for s in range(S):
        if v[s] and not (newton_polish(L, rev, scale, Rd, pd, q + 6 * s, w) < CANDIDATE_TOL):
            v[s] = False


def polish(Chain chain, Q, valid, targets, double scale, int threads=0):
    """Newton-polish closed-form branches on a 6-joint chain's exact forward kinematics, in place.

    Q (N, S, 6) float64 C-contiguous branches, valid (N, S) bool (only those are polished; a branch
    whose residual stays above 1e-6 is marked invalid), targets (N, 4, 4). The branches of an arm within
    calibration error of a closed-form class, solved on the ideal arm (``kinematics.near_class``). The
    targets split over ``threads`` (0: automatic, see ``threads.pyx``), the same bits on any.
    """
    cdef cnp.ndarray Qa = <cnp.ndarray>Q
    cdef cnp.ndarray Va = <cnp.ndarray>valid
    cdef cnp.ndarray Ta = np.ascontiguousarray(targets, dtype=np.float64)
    if chain.n != 6 or not (cnp.PyArray_TYPE(Qa) == cnp.NPY_DOUBLE and cnp.PyArray_IS_C_CONTIGUOUS(Qa)
                            and cnp.PyArray_NDIM(Qa) == 3 and cnp.PyArray_DIM(Qa, 2) == 6
                            and cnp.PyArray_TYPE(Va) == cnp.NPY_BOOL and cnp.PyArray_IS_C_CONTIGUOUS(Va)
                            and cnp.PyArray_SIZE(Va) == cnp.PyArray_DIM(Qa, 0) * cnp.PyArray_DIM(Qa, 1)
                            and cnp.PyArray_SIZE(Ta) == 16 * cnp.PyArray_DIM(Qa, 0)):
        raise ValueError("polish: expected a 6-joint chain, Q (N, S, 6) float64, valid (N, S) bool, targets (N, 4, 4)")
    cdef Py_ssize_t N = cnp.PyArray_DIM(Qa, 0), S = cnp.PyArray_DIM(Qa, 1), k
    cdef double* q = <double*>cnp.PyArray_DATA(Qa)
    cdef unsigned char* v = <unsigned char*>cnp.PyArray_DATA(Va)
    cdef const double* t = <const double*>cnp.PyArray_DATA(Ta)
    # a target's branches take ~10 us: threads pay from a few dozen targets each
    cdef int nt = batch_threads(threads, N, 32)
    if nt <= 1:     # no OpenMP region for one thread
        with nogil:
            for k in range(N):
                polish_target(chain.L, chain.rev, scale, t + 16 * k, q + 6 * S * k, v + S * k, S)
        return
    for k in prange(N, nogil=True, num_threads=nt, schedule="dynamic", chunksize=4):
        polish_target(chain.L, chain.rev, scale, t + 16 * k, q + 6 * S * k, v + S * k, S)
