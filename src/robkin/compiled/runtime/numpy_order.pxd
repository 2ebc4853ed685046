# cython: language_level=3
"""Arithmetic in NumPy's order, for compiled code that must give the same bits as NumPy expressions it
replaced (``cimport`` it, nothing to import): the element-wise products and sums in the order the
expressions evaluate them, and NumPy's ``@`` of 4x4 matrices, which sums each entry as a chain of fused
multiply-adds in k order (what the x86-64 OpenBLAS that NumPy ships computes on FMA-capable machines;
``tests/test_convert_stages.py`` checks it against NumPy on every run). Used by the frame quantities
of ``robkin.frame_stacks`` (``rigid.frame_stacks``) and the conversions' stages (``frames.pyx``).
"""

from libc.math cimport fma, sqrt, INFINITY


cdef inline void gemm_fma(const double* A, const double* B, double* out) noexcept nogil:
    """out = A B (4x4 row-major) as NumPy's ``@`` computes it: each entry a chain of fused
    multiply-adds over k = 0..3."""
    cdef int i, j
    cdef double s
    for i in range(4):
        for j in range(4):
            s = A[4 * i] * B[j]
            s = fma(A[4 * i + 1], B[4 + j], s)
            s = fma(A[4 * i + 2], B[8 + j], s)
            out[4 * i + j] = fma(A[4 * i + 3], B[12 + j], s)


cdef inline double norm3_np(double x, double y, double z) noexcept nogil:
    """``np.linalg.norm`` of (x, y, z): the squares summed in order."""
    return sqrt((x * x + y * y) + z * z)


cdef inline double frames_scale(const double* frames, Py_ssize_t n) noexcept nogil:
    """``frame_stacks.frame_scales`` of one robot's GJD frames (n + 1 poses), with NumPy's sums."""
    cdef Py_ssize_t i
    cdef const double* T
    cdef double e, feet = -INFINITY, origins = -INFINITY, s, v
    for i in range(n):
        T = frames + 16 * i
        e = (T[3] * T[2] + T[7] * T[6]) + T[11] * T[10]   # p . z, the einsum's order
        v = norm3_np(T[3] - e * T[2], T[7] - e * T[6], T[11] - e * T[10])
        if v > feet or v != v:
            feet = v
    for i in range(n + 1):
        T = frames + 16 * i
        v = norm3_np(T[3], T[7], T[11])
        if v > origins or v != v:
            origins = v
    T = frames + 16 * n
    s = norm3_np(T[3], T[7], T[11])
    if not (s >= feet):   # np.maximum (the frames are finite)
        s = feet
    if s <= 1e-9 * origins:   # the tolerances' reasons: frame_stacks.frame_scales
        s = origins
    if not (s >= 1e-3 * origins):
        s = 1e-3 * origins
    return s if s > 0 else 1.0


cdef inline void frames_local(const double* frames, Py_ssize_t n, double* L) noexcept nogil:
    """``frame_stacks.local_transforms`` of one robot's GJD frames (n + 1 poses) into L (n + 1 poses):
    L_1 = J_1, L_i = J_{i-1}^-1 J_i, with ``se3.inv`` (R^T, -R^T p) and NumPy's matrix product."""
    cdef Py_ssize_t i
    cdef int r
    cdef const double* T
    cdef double V[16]
    for r in range(16):
        L[r] = frames[r]
    for i in range(1, n + 1):
        T = frames + 16 * (i - 1)
        for r in range(3):
            V[4 * r], V[4 * r + 1], V[4 * r + 2] = T[r], T[4 + r], T[8 + r]
            V[4 * r + 3] = -((T[r] * T[3] + T[4 + r] * T[7]) + T[8 + r] * T[11])
        V[12], V[13], V[14], V[15] = 0.0, 0.0, 0.0, 1.0
        gemm_fma(V, frames + 16 * i, L + 16 * i)
