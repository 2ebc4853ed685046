# cython: language_level=3
"""The choice among closed-form branches of one target, and the distinct solutions, as ``cdef inline``
functions.

Shared by ``solutions`` (a batch) and the closed-form kernels' single-target entries
(``closed_form_kernel``), so one target and a batch pick their answers by the same code.
"""

from libc.math cimport fabs, sqrt, INFINITY
cimport numpy as cnp
from robkin.compiled.chain.fk cimport tool_poses
from robkin.compiled.ik.pose_check cimport finite_row, tool_errors, tool_pose_errors


cdef inline void insert_by_distance(Py_ssize_t* order, Py_ssize_t m, const double* dist,
                                    Py_ssize_t i) noexcept nogil:
    """Insert index i into order[0:m] (indices sorted by dist) after those at the same distance:
    insertion sort, stable, and the lists are short (8 branches, or 1 + restarts starts)."""
    cdef Py_ssize_t a = m
    while a > 0 and dist[order[a - 1]] > dist[i]:
        order[a] = order[a - 1]
        a -= 1
    order[a] = i


cdef inline void check_branches(const double* L, const unsigned char* rev, Py_ssize_t n, const double* q,
                                const Py_ssize_t* order, Py_ssize_t a0, Py_ssize_t a1, const double* T,
                                double* work, double* err) noexcept nogil:
    """The forward-kinematics check of the branches q[order[a]] (n,), a0 <= a < a1, towards the target
    T (4x4 row-major): their tool poses in one block walk of ``fk.pxd`` (``tool_poses``), then
    err[2 a], err[2 a + 1] = position and orientation errors (``pose_check.tool_pose_errors``, full
    pose; inf for a branch that is not finite). work: (a1 - a0) (n + 16) doubles of scratch."""
    cdef Py_ssize_t a, c = 0, j
    cdef const double* b
    cdef double* Qb = work
    cdef double* Tb = work + (a1 - a0) * n
    cdef double full_pose[6]        # the mask of tool_pose_errors: every component
    for j in range(6):
        full_pose[j] = 1.0
    if a1 - a0 == 1:                # one row: walked in place (the same bits as in a block)
        tool_errors(L, rev, <int>n, q + order[a0] * n, T, full_pose, err + 2 * a0, err + 2 * a0 + 1)
        return
    for a in range(a0, a1):         # the finite rows, in order, as one (c, n) block
        b = q + order[a] * n
        if finite_row(b, <int>n):
            for j in range(n):
                Qb[c * n + j] = b[j]
            c += 1
    tool_poses(L, rev, <int>n, Qb, c, Tb)
    c = 0
    for a in range(a0, a1):
        if finite_row(q + order[a] * n, <int>n):
            tool_pose_errors(Tb + 16 * c, T, full_pose, err + 2 * a, err + 2 * a + 1)
            c += 1
        else:
            err[2 * a] = INFINITY
            err[2 * a + 1] = INFINITY


cdef inline Py_ssize_t check_work_size(Py_ssize_t S, Py_ssize_t n, bint every) noexcept nogil:
    """Doubles of scratch ``nearest_branch`` needs: the candidates' errors (2 S) and the block of rows
    walked at once with their tool poses (all S with ``every``, else one)."""
    return 2 * S + (S if every else 1) * (n + 16)


cdef inline Py_ssize_t nearest_branch(const double* L, const unsigned char* rev, Py_ssize_t n,
                                      const double* q, const unsigned char* v, Py_ssize_t S,
                                      const double* T, const double* r, const double* lim,
                                      double length_unit, double tol_position, double tol_orientation,
                                      double limit_tol, bint every, unsigned char* reached,
                                      double* dist, Py_ssize_t* order, Py_ssize_t* m_out, double* ep,
                                      double* eo, double* work) noexcept nogil:
    """The index of the branch q[s] (S, n) nearest r (n,) that truly reaches the target T (4x4
    row-major), or -1; see ``solutions.nearest_verified`` for what counts and the order of the search.

    v (S,): the solver's valid flags; lim (n, 2) row-major; dist: scratch of S entries; order (S,)
    and m_out: the candidates (valid, within the limits), nearest first, and their number; reached
    (S,) is set (1 for the branches found to count); ep, eo: the errors of the chosen branch (inf if
    none); work: ``check_work_size(S, n, every)`` doubles of scratch. With ``every`` all candidates
    are checked in one block FK walk; without, one at a time, nearest first, until one counts (usually
    the first).
    """
    cdef Py_ssize_t m = 0, s, j, a, best = -1
    cdef const double* b
    cdef double x, d, e_p, e_o
    cdef bint fits
    cdef double* err = work                 # (S, 2): the candidates' errors, in their order
    # candidates (valid, within the limits) sorted by distance, ties in index order: the first that
    # counts is numpy.argmin's choice
    for s in range(S):
        reached[s] = 0
        if not v[s]:
            continue
        b = q + s * n
        fits = True
        d = 0.0
        for j in range(n):
            if not (b[j] >= lim[2 * j] - limit_tol and b[j] <= lim[2 * j + 1] + limit_tol):
                fits = False
                break
            x = b[j] - r[j]
            if not rev[j]:
                x /= length_unit
            d += x * x
        if not fits:
            continue
        dist[s] = sqrt(d)
        insert_by_distance(order, m, dist, s)
        m += 1
    m_out[0] = m
    ep[0] = INFINITY
    eo[0] = INFINITY
    if every:
        check_branches(L, rev, n, q, order, 0, m, T, work + 2 * S, err)
    for a in range(m):
        if not every:
            check_branches(L, rev, n, q, order, a, a + 1, T, work + 2 * S, err)
        s = order[a]
        e_p = err[2 * a]
        e_o = err[2 * a + 1]
        if not (e_p <= tol_position and e_o <= tol_orientation):
            continue
        reached[s] = 1
        if best < 0:
            best = s
            ep[0] = e_p
            eo[0] = e_o
            if not every:
                break
    return best


cdef inline Py_ssize_t keep_distinct(const double* q, Py_ssize_t n, const Py_ssize_t* order, Py_ssize_t m,
                                     const unsigned char* take, const double* unit, double tol,
                                     Py_ssize_t* kept) noexcept nogil:
    """The rows q[order[a]] (n,) for a = 0..m-1 (only those with ``take[row]``, all if take is NULL),
    each dropped if a row kept before it differs by at most ``tol`` in every |dq / unit| (unit (n,):
    1 rad for revolute joints, the robot's size for prismatic ones). Writes the kept row indices, in
    order, to kept and returns their number."""
    cdef Py_ssize_t a, b, i, j, k = 0
    cdef bint duplicate
    for a in range(m):
        i = order[a]
        if take != NULL and not take[i]:
            continue
        duplicate = False
        for b in range(k):
            duplicate = True
            for j in range(n):
                if fabs(q[i * n + j] - q[kept[b] * n + j]) / unit[j] > tol:
                    duplicate = False
                    break
            if duplicate:
                break
        if not duplicate:
            kept[k] = i
            k += 1
    return k


cdef inline void put_row(const double* q, Py_ssize_t n, const double* template, const Py_ssize_t* where,
                         Py_ssize_t m, double* o) noexcept nogil:
    """o (n,) = q (n,); with a template (m,), o (m,) = the template with q[j] at where[j] (the free joints
    of a longer arm, ``kinematics.lock``)."""
    cdef Py_ssize_t j
    if template == NULL:
        for j in range(n):
            o[j] = q[j]
        return
    for j in range(m):
        o[j] = template[j]
    for j in range(n):
        o[where[j]] = q[j]


cdef inline cnp.ndarray rows_array(const double* q, Py_ssize_t n, const Py_ssize_t* kept, Py_ssize_t k,
                                   const double* template=NULL, const Py_ssize_t* where=NULL, Py_ssize_t m=0):
    """A new (k, n) float64 array of the rows q[kept[a]] (n,); with a template (m,), (k, m) rows
    (``put_row``)."""
    cdef Py_ssize_t w = n if template == NULL else m
    cdef cnp.npy_intp dims[2]
    dims[0] = k
    dims[1] = w
    cdef cnp.ndarray out = cnp.PyArray_EMPTY(2, dims, cnp.NPY_DOUBLE, 0)
    cdef double* o = <double*>cnp.PyArray_DATA(out)
    cdef Py_ssize_t a
    for a in range(k):
        put_row(q + kept[a] * n, n, template, where, m, o + a * w)
    return out
