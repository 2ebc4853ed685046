"""Solution bookkeeping shared by the IK methods: distinct solutions, nearest to a preference first.

``distinct_sorted`` replaces a Python loop over rows (dozens of small numpy calls per target) by one
compiled pass; ``kinematics.ik`` calls it for every target of an ``all_solutions=True`` request.
"""

cimport numpy as cnp
from libc.math cimport fabs, sqrt
from libc.stdlib cimport free, malloc
from robkin.compiled.subproblems cimport c_doubles, new_array

cnp.import_array()


def distinct_sorted(Q, ref, scale, double tol):
    """Rows of Q (k, n) sorted by the distance |(q - ref) / scale| to ref (n,) (stable: ties keep their
    order), each dropped if a row kept before it differs by at most ``tol`` in every |dq / scale|.

    ``scale`` (n,): the unit of each joint (1 rad for revolute ones, the robot size for prismatic).
    Returns a new (m, n) array, m <= k.
    """
    cdef Py_ssize_t n = len(ref)
    cdef cnp.ndarray A = c_doubles(Q, 2, n, "Q")
    cdef cnp.ndarray R = c_doubles(ref, 1, n, "ref")
    cdef cnp.ndarray U = c_doubles(scale, 1, n, "scale")
    cdef Py_ssize_t k = cnp.PyArray_DIM(A, 0), i, j, a, m = 0
    cdef const double* q = <const double*>cnp.PyArray_DATA(A)
    cdef const double* r = <const double*>cnp.PyArray_DATA(R)
    cdef const double* u = <const double*>cnp.PyArray_DATA(U)
    cdef double* dist = <double*>malloc(max(k, 1) * sizeof(double))
    cdef Py_ssize_t* order = <Py_ssize_t*>malloc(max(k, 1) * sizeof(Py_ssize_t))
    cdef Py_ssize_t* kept = <Py_ssize_t*>malloc(max(k, 1) * sizeof(Py_ssize_t))
    cdef double s, x
    cdef bint duplicate
    if dist == NULL or order == NULL or kept == NULL:
        free(dist)
        free(order)
        free(kept)
        raise MemoryError()
    try:
        for i in range(k):
            s = 0.0
            for j in range(n):
                x = (q[i * n + j] - r[j]) / u[j]
                s += x * x
            dist[i] = sqrt(s)
            # insertion sort: stable, and k is small (8 branches, or 1 + restarts starts)
            a = i
            while a > 0 and dist[order[a - 1]] > dist[i]:
                order[a] = order[a - 1]
                a -= 1
            order[a] = i
        for a in range(k):
            i = order[a]
            duplicate = False
            for b in range(m):
                duplicate = True
                for j in range(n):
                    if fabs(q[i * n + j] - q[kept[b] * n + j]) / u[j] > tol:
                        duplicate = False
                        break
                if duplicate:
                    break
            if not duplicate:
                kept[m] = i
                m += 1
        out = new_array(2, m, n, 0, cnp.NPY_DOUBLE)
        for a in range(m):
            for j in range(n):
                (<double*>cnp.PyArray_DATA(out))[a * n + j] = q[kept[a] * n + j]
        return out
    finally:
        free(dist)
        free(order)
        free(kept)
