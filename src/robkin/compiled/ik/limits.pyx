# cython: language_level=3
"""Joint-limit bookkeeping for solutions: whole turns of revolute joints into the limits, and the
check that every joint lies within them (the kernels behind ``kinematics.limits``)."""

cimport numpy as cnp
from robkin.compiled.ik.subproblems cimport wrap_into_limits

import numpy as np

cnp.import_array()

def wrap(Q, lower, upper, revolute, ref, double tol):
    """Revolute values of Q (M, n) shifted by whole turns into [lower, upper], nearest to ref (M, n).

    Returns the shifted copy (M, n) and ok (M,) bool: every joint within its limits up to ``tol``.
    Prismatic joints are only checked. Where no turn fits, the turn nearest the range is taken (and ok
    is False), as ``numpy.clip`` with crossed bounds would.
    """
    cdef cnp.ndarray Qa = np.ascontiguousarray(Q, dtype=np.float64)
    cdef cnp.ndarray Ra = np.ascontiguousarray(ref, dtype=np.float64)
    cdef cnp.ndarray loa = np.ascontiguousarray(lower, dtype=np.float64)
    cdef cnp.ndarray hia = np.ascontiguousarray(upper, dtype=np.float64)
    cdef cnp.ndarray reva = np.ascontiguousarray(revolute, dtype=np.uint8)
    if Qa.ndim != 2 or Ra.ndim != 2 or Qa.shape[0] != Ra.shape[0] or Qa.shape[1] != Ra.shape[1] \
            or loa.ndim != 1 or hia.ndim != 1 or reva.ndim != 1 or loa.shape[0] != Qa.shape[1] \
            or hia.shape[0] != Qa.shape[1] or reva.shape[0] != Qa.shape[1]:
        raise ValueError("wrap: expected Q and ref (M, n), lower, upper, revolute (n,)")
    cdef Py_ssize_t M = Qa.shape[0], n = Qa.shape[1], i, j
    cdef const double* q = <const double*>cnp.PyArray_DATA(Qa)
    cdef const double* r = <const double*>cnp.PyArray_DATA(Ra)
    cdef const double* lo = <const double*>cnp.PyArray_DATA(loa)
    cdef const double* hi = <const double*>cnp.PyArray_DATA(hia)
    cdef const unsigned char* rev = <const unsigned char*>cnp.PyArray_DATA(reva)
    cdef cnp.npy_intp dims[2]
    dims[0] = M
    dims[1] = n
    cdef cnp.ndarray out_arr = cnp.PyArray_EMPTY(2, dims, cnp.NPY_DOUBLE, 0)
    cdef cnp.ndarray ok_arr = cnp.PyArray_EMPTY(1, dims, cnp.NPY_BOOL, 0)
    cdef double* out = <double*>cnp.PyArray_DATA(out_arr)
    cdef unsigned char* ok = <unsigned char*>cnp.PyArray_DATA(ok_arr)
    with nogil:
        for i in range(M):
            for j in range(n):
                out[n * i + j] = q[n * i + j]
            # the one wrapping rule, shared with the closed-form kernels
            ok[i] = wrap_into_limits(out + n * i, r + n * i, lo, hi, rev, n, tol)
    return out_arr, ok_arr
