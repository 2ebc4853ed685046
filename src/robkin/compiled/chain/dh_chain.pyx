# cython: language_level=3
"""Frames along a standard-DH chain for many designs and configurations at once (the synthesis
optimiser's model, whose parameters change at every evaluation, so no ``Robot`` is built)."""

cimport numpy as cnp
from libc.math cimport sin, cos
from libc.stdlib cimport malloc, free
from robkin.compiled.runtime.linalg cimport tf_mul, tf_copy, tf_identity, tall_volume

import numpy as np

cnp.import_array()


def dh_frames(a, d, alpha, theta):
    """Frames {0}..{n} of T = prod_i Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i).

    Parameters
    ----------
    a, d, alpha : (B, n) arrays
        DH parameters of B designs (lengths, radians).
    theta : (B, K, n) array
        Joint angles of K configurations per design (radians).

    Returns
    -------
    o, z : (B, K, n+1, 3) arrays
        Origins and z axes of frames {0} (the base) to {n}.
    x : (B, K, n, 3) array
        x axes of frames {1}..{n}.
    R : (B, K, 3, 3) array
        Rotation of frame {n} (the tool).
    """
    cdef const double[:, ::1] A = np.ascontiguousarray(a, dtype=np.float64)
    cdef const double[:, ::1] D = np.ascontiguousarray(d, dtype=np.float64)
    cdef const double[:, ::1] AL = np.ascontiguousarray(alpha, dtype=np.float64)
    cdef const double[:, :, ::1] TH = np.ascontiguousarray(theta, dtype=np.float64)
    cdef Py_ssize_t B = TH.shape[0], K = TH.shape[1], n = TH.shape[2]
    if A.shape[0] != B or D.shape[0] != B or AL.shape[0] != B or A.shape[1] != n or D.shape[1] != n \
            or AL.shape[1] != n:
        raise ValueError("dh_frames: expected a, d, alpha (B, n) and theta (B, K, n)")
    o_arr = np.empty((B, K, n + 1, 3))
    z_arr = np.empty((B, K, n + 1, 3))
    x_arr = np.empty((B, K, n, 3))
    R_arr = np.empty((B, K, 3, 3))
    cdef double[:, :, :, ::1] o = o_arr
    cdef double[:, :, :, ::1] z = z_arr
    cdef double[:, :, :, ::1] x = x_arr
    cdef double[:, :, :, ::1] R = R_arr
    cdef double T[16]
    cdef double M[16]
    cdef double out[16]
    cdef double ct, st, ca, sa
    cdef Py_ssize_t b, k, i, r
    with nogil:
        for b in range(B):
            for k in range(K):
                tf_identity(T)
                for r in range(3):
                    o[b, k, 0, r] = T[4 * r + 3]
                    z[b, k, 0, r] = T[4 * r + 2]
                for i in range(n):
                    ct = cos(TH[b, k, i])
                    st = sin(TH[b, k, i])
                    ca = cos(AL[b, i])
                    sa = sin(AL[b, i])
                    M[0] = ct
                    M[1] = -st * ca
                    M[2] = st * sa
                    M[3] = A[b, i] * ct
                    M[4] = st
                    M[5] = ct * ca
                    M[6] = -ct * sa
                    M[7] = A[b, i] * st
                    M[8] = 0.0
                    M[9] = sa
                    M[10] = ca
                    M[11] = D[b, i]
                    tf_mul(T, M, out)
                    tf_copy(out, T)
                    for r in range(3):
                        o[b, k, i + 1, r] = T[4 * r + 3]
                        z[b, k, i + 1, r] = T[4 * r + 2]
                        x[b, k, i, r] = T[4 * r]
                for r in range(3):
                    R[b, k, r, 0] = T[4 * r]
                    R[b, k, r, 1] = T[4 * r + 1]
                    R[b, k, r, 2] = T[4 * r + 2]
    return o_arr, z_arr, x_arr, R_arr


cdef inline void dh_link(double a, double d, double ct, double st, double ca, double sa,
                         double* M) noexcept nogil:
    """M = Rz(theta) Tz(d) Tx(a) Rx(alpha) (4x4, last row written by the caller's product)."""
    M[0] = ct
    M[1] = -st * ca
    M[2] = st * sa
    M[3] = a * ct
    M[4] = st
    M[5] = ct * ca
    M[6] = -ct * sa
    M[7] = a * st
    M[8] = 0.0
    M[9] = sa
    M[10] = ca
    M[11] = d


def dh_volumes(a, d, alpha, theta, length, bint pose):
    """Product of the singular values of each configuration's scaled geometric Jacobian.

    Parameters
    ----------
    a, d, alpha : (B, n) arrays
        DH parameters of B designs (lengths, radians).
    theta : (B, K, n) array
        Joint angles (radians).
    length : (B,) array
        Each design's length L: the linear-velocity rows are divided by it (scale-free measure).
    pose : bool
        Rows [v / L; w] (6 x n) if True, v / L only (3 x n) if False.

    Returns
    -------
    (B, K) array
        prod of the min(n, rows) singular values (0 at a singular configuration).
    """
    cdef const double[:, ::1] A = np.ascontiguousarray(a, dtype=np.float64)
    cdef const double[:, ::1] D = np.ascontiguousarray(d, dtype=np.float64)
    cdef const double[:, ::1] AL = np.ascontiguousarray(alpha, dtype=np.float64)
    cdef const double[:, :, ::1] TH = np.ascontiguousarray(theta, dtype=np.float64)
    cdef const double[::1] LEN = np.ascontiguousarray(length, dtype=np.float64)
    cdef Py_ssize_t B = TH.shape[0], K = TH.shape[1], n = TH.shape[2]
    if A.shape[0] != B or D.shape[0] != B or AL.shape[0] != B or LEN.shape[0] != B or A.shape[1] != n \
            or D.shape[1] != n or AL.shape[1] != n:
        raise ValueError("dh_volumes: expected a, d, alpha (B, n), theta (B, K, n), length (B,)")
    out_arr = np.empty((B, K))
    cdef double[:, ::1] out = out_arr
    cdef int rows = 6 if pose else 3
    cdef int m = n if n >= rows else rows          # tall orientation: m x k, m >= k
    cdef int k = rows if n >= rows else n
    cdef double* zo = <double*>malloc(6 * n * sizeof(double))     # z_{i-1}, o_{i-1} per joint
    cdef double* M = <double*>malloc(6 * n * sizeof(double))
    cdef double T[16]
    cdef double L[16]
    cdef double P[16]
    cdef double jac[6]
    cdef double dx, dy, dz, zx, zy, zz, inv_len
    cdef Py_ssize_t b, c, i, r
    if zo == NULL or M == NULL:
        free(zo)
        free(M)
        raise MemoryError()
    with nogil:
        for b in range(B):
            inv_len = 1.0 / LEN[b]
            for c in range(K):
                tf_identity(T)
                for i in range(n):
                    for r in range(3):
                        zo[6 * i + r] = T[4 * r + 2]
                        zo[6 * i + 3 + r] = T[4 * r + 3]
                    dh_link(A[b, i], D[b, i], cos(TH[b, c, i]), sin(TH[b, c, i]), cos(AL[b, i]),
                            sin(AL[b, i]), L)
                    tf_mul(T, L, P)
                    tf_copy(P, T)
                for i in range(n):
                    zx = zo[6 * i]
                    zy = zo[6 * i + 1]
                    zz = zo[6 * i + 2]
                    dx = T[3] - zo[6 * i + 3]
                    dy = T[7] - zo[6 * i + 4]
                    dz = T[11] - zo[6 * i + 5]
                    jac[0] = (zy * dz - zz * dy) * inv_len
                    jac[1] = (zz * dx - zx * dz) * inv_len
                    jac[2] = (zx * dy - zy * dx) * inv_len
                    jac[3] = zx
                    jac[4] = zy
                    jac[5] = zz
                    for r in range(rows):
                        if n >= rows:
                            M[i * k + r] = jac[r]      # J^T: joint i is row i
                        else:
                            M[r * k + i] = jac[r]      # J: joint i is column i
                out[b, c] = tall_volume(M, m, k)
    free(zo)
    free(M)
    return out_arr
