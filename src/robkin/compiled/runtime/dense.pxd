# cython: language_level=3
"""Small dense linear algebra of any size (``cimport`` it, nothing to import): the solves that the
least-squares iterations share (``lm`` for inverse kinematics, ``box_lsq`` for the synthesis optimiser).

Matrices are plain C arrays of doubles, row-major (``A[i * m + j]``). Everything is ``nogil`` and
allocation-free. Fixed 3 x 3 / 4 x 4 helpers live in ``linalg.pxd``.
"""

from libc.math cimport sqrt


cdef inline bint cholesky_solve(double* A, double* b, int m) noexcept nogil:
    """Solve A x = b in place (x in b) for a symmetric positive definite A (m x m, lower triangle used,
    overwritten by its Cholesky factor). False if A is not numerically positive definite."""
    cdef int i, j, k
    cdef double s
    for j in range(m):
        s = A[j * m + j]
        for k in range(j):
            s -= A[j * m + k] * A[j * m + k]
        if not (s > 0.0):
            return False
        A[j * m + j] = sqrt(s)
        for i in range(j + 1, m):
            s = A[i * m + j]
            for k in range(j):
                s -= A[i * m + k] * A[j * m + k]
            A[i * m + j] = s / A[j * m + j]
    for i in range(m):
        s = b[i]
        for k in range(i):
            s -= A[i * m + k] * b[k]
        b[i] = s / A[i * m + i]
    for i in range(m - 1, -1, -1):
        s = b[i]
        for k in range(i + 1, m):
            s -= A[k * m + i] * b[k]
        b[i] = s / A[i * m + i]
    return True
