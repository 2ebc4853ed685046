# cython: language_level=3
"""Joint-limit bookkeeping for solutions: whole turns of revolute joints into the limits, and the
check that every joint lies within them (the kernels behind ``kinematics.limits``)."""

cimport numpy as cnp
from libc.math cimport ceil, floor, rint, M_PI

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
    cdef double two_pi = 2.0 * M_PI, x, k, k_lo, k_hi
    with nogil:
        for i in range(M):
            ok[i] = 1
            for j in range(n):
                x = q[n * i + j]
                if rev[j]:
                    k_lo = ceil((lo[j] - tol - x) / two_pi)      # -inf where unlimited
                    k_hi = floor((hi[j] + tol - x) / two_pi)     # +inf where unlimited
                    k = rint((r[n * i + j] - x) / two_pi)        # half to even, as numpy.round
                    if k < k_lo:
                        k = k_lo
                    if k > k_hi:
                        k = k_hi
                    x = x + k * two_pi
                out[n * i + j] = x
                if not (x >= lo[j] - tol and x <= hi[j] + tol):
                    ok[i] = 0
    return out_arr, ok_arr
