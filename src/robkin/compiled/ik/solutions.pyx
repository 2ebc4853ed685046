"""Solution bookkeeping shared by the IK methods: distinct solutions, nearest to a preference first.

``distinct_sorted`` replaces a Python loop over rows (dozens of small numpy calls per target) by one
compiled pass; ``kinematics.ik`` calls it for the numeric method's ``all_solutions=True``.
``nearest_verified`` checks closed-form branches by forward kinematics and picks the one nearest the
preferred configuration for a batch, and with ``every`` lists every distinct verified solution per
target in the same pass (one pass, no per-target numpy plumbing).
"""

cimport numpy as cnp
from libc.math cimport sqrt, NAN
from libc.stdlib cimport free, malloc
from robkin.compiled.chain.fk cimport Chain
from robkin.compiled.ik.nearest cimport (check_work_size, insert_by_distance, keep_distinct, nearest_branch,
                                      rows_array)
from robkin.compiled.ik.subproblems cimport c_doubles, new_array
from robkin.compiled.runtime.threads cimport batch_threads
from cython.parallel cimport parallel, prange

cnp.import_array()

cdef enum:
    # checking a target's branches takes ~0.5-2 us: threads pay from a few hundred targets per thread;
    # chunks of targets keep the dynamic schedule's bookkeeping small beside them
    MIN_TARGETS_PER_THREAD = 256
    TARGETS_PER_CHUNK = 32


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
    cdef Py_ssize_t k = cnp.PyArray_DIM(A, 0), i, j, m
    cdef const double* q = <const double*>cnp.PyArray_DATA(A)
    cdef const double* r = <const double*>cnp.PyArray_DATA(R)
    cdef const double* u = <const double*>cnp.PyArray_DATA(U)
    cdef double* dist = <double*>malloc(max(k, 1) * sizeof(double))
    cdef Py_ssize_t* order = <Py_ssize_t*>malloc(max(k, 1) * sizeof(Py_ssize_t))
    cdef Py_ssize_t* kept = <Py_ssize_t*>malloc(max(k, 1) * sizeof(Py_ssize_t))
    cdef double s, x
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
            insert_by_distance(order, i, dist, i)
        m = keep_distinct(q, n, order, k, NULL, u, tol, kept)
        return rows_array(q, n, kept, m)
    finally:
        free(dist)
        free(order)
        free(kept)


cdef struct Check:
    # one batch of ``nearest_verified``: inputs, outputs, settings (each target writes only its own rows)
    const double* L
    const unsigned char* rev
    Py_ssize_t n
    Py_ssize_t S
    const double* q
    const unsigned char* v
    const double* T
    const double* r
    const double* lim
    const double* unit
    double length_unit
    double tol_position
    double tol_orientation
    double limit_tol
    double same_tol
    bint every
    double* qo
    unsigned char* ok
    double* ep
    double* eo
    Py_ssize_t* kept        # with every: (N, S) the distinct verified branches' rows per target
    Py_ssize_t* m           # with every: (N,) how many


cdef inline Py_ssize_t check_target(const Check* C, Py_ssize_t k, char* scratch) noexcept nogil:
    """Target k of ``nearest_verified`` with a thread's scratch (``scratch_bytes``); 1 if no branch counts."""
    cdef Py_ssize_t n = C.n, S = C.S, S1 = max(C.S, 1), j, best, m
    cdef double* dist = <double*>scratch
    cdef Py_ssize_t* order = <Py_ssize_t*>(dist + S1 + check_work_size(S, n, C.every))
    cdef unsigned char* reached = <unsigned char*>(order + S1)
    best = nearest_branch(C.L, C.rev, n, C.q + k * S * n, C.v + k * S, S, C.T + 16 * k, C.r + k * n, C.lim,
                          C.length_unit, C.tol_position, C.tol_orientation, C.limit_tol, C.every, reached,
                          dist, order, &m, C.ep + k, C.eo + k, dist + S1)
    C.ok[k] = best >= 0
    for j in range(n):
        C.qo[k * n + j] = C.q[(k * S + best) * n + j] if best >= 0 else NAN
    if C.every:
        C.m[k] = keep_distinct(C.q + k * S * n, n, order, m, reached, C.unit, C.same_tol, C.kept + k * S)
    return best < 0


cdef inline Py_ssize_t scratch_bytes(Py_ssize_t S, Py_ssize_t n, bint every) noexcept nogil:
    """Bytes of scratch ``check_target`` needs: per branch a distance, an order slot and a reached flag,
    and ``nearest_branch``'s work."""
    cdef Py_ssize_t S1 = max(S, 1)
    return (S1 + check_work_size(S, n, every)) * sizeof(double) + S1 * sizeof(Py_ssize_t) + S1


def nearest_verified(Chain chain, Q, valid, targets, q_ref, limits, double length_unit,
                     double tol_position, double tol_orientation, double limit_tol, bint every,
                     double same_tol=0.0, int threads=0):
    """Per target, the closed-form branch nearest the preference among those that truly reach it.

    A branch Q[k, s] (n,) counts when ``valid[k, s]`` (it exists and respects the limits, as the solver
    says), every joint is within its limits (n, 2) up to ``limit_tol``, and an independent forward
    kinematics (the walk of ``Robot.fk``, ``nearest.check_branches``) puts the tool within
    ``tol_position`` (length units) and ``tol_orientation`` (radians) of targets[k] (full pose). Among
    those, the nearest to q_ref[k] (n,) by |(q - q_ref) / unit| (the first on ties, as
    ``numpy.argmin``), the unit being 1 rad for revolute joints and ``length_unit`` (the robot's size)
    for prismatic ones. Branches are checked nearest first: with ``every`` False the search stops at
    the first that counts (one forward kinematics per target in the usual case); with ``every`` True
    all are checked, in one block walk per target, for the list of all solutions.

    Parameters: Q (N, S, n), valid (N, S) bool, targets (N, 4, 4), q_ref (N, n), limits (n, 2);
    same_tol: with ``every``, two solutions are the same when no |dq / unit| exceeds it; threads: the
    targets split over at most that many (0: automatic, see ``threads.pyx``; the same bits on any).
    Returns q (N, n) (NaN where no branch counts), success (N,) bool, the solutions (with ``every``:
    per target a new (S_k, n) array of the distinct branches that count, nearest q_ref first, as
    ``distinct_sorted`` orders them; else None), position and orientation errors (N,) of q (inf where
    q is NaN), and the number of targets without a branch that counts.
    """
    cdef Py_ssize_t n = chain.n
    cdef cnp.ndarray Qa = cnp.PyArray_FROM_OTF(Q, cnp.NPY_DOUBLE, cnp.NPY_ARRAY_C_CONTIGUOUS | cnp.NPY_ARRAY_ALIGNED)
    if cnp.PyArray_NDIM(Qa) != 3 or cnp.PyArray_DIM(Qa, 2) != n:
        raise ValueError(f"Q: expected shape (N, S, {n}), got {(<object>Qa).shape}")
    cdef Py_ssize_t N = cnp.PyArray_DIM(Qa, 0), S = cnp.PyArray_DIM(Qa, 1), k, j
    cdef cnp.ndarray Va = cnp.PyArray_FROM_OTF(valid, cnp.NPY_BOOL, cnp.NPY_ARRAY_C_CONTIGUOUS | cnp.NPY_ARRAY_ALIGNED)
    cdef cnp.ndarray Ta = c_doubles(targets, 3, 4, "targets")
    cdef cnp.ndarray Ra = c_doubles(q_ref, 2, n, "q_ref")
    cdef cnp.ndarray La = c_doubles(limits, 2, 2, "limits")
    if cnp.PyArray_NDIM(Va) != 2 or cnp.PyArray_DIM(Va, 0) != N or cnp.PyArray_DIM(Va, 1) != S \
            or cnp.PyArray_DIM(Ta, 0) != N or cnp.PyArray_DIM(Ra, 0) != N or cnp.PyArray_DIM(La, 0) != n:
        raise ValueError(f"nearest_verified: expected valid ({N}, {S}), targets ({N}, 4, 4), q_ref ({N}, {n}), "
                         f"limits ({n}, 2)")
    cdef Check C
    C.L, C.rev, C.n, C.S = chain.L, chain.rev, n, S
    C.q = <const double*>cnp.PyArray_DATA(Qa)
    C.v = <const unsigned char*>cnp.PyArray_DATA(Va)
    C.T = <const double*>cnp.PyArray_DATA(Ta)
    C.r = <const double*>cnp.PyArray_DATA(Ra)
    C.lim = <const double*>cnp.PyArray_DATA(La)
    C.length_unit, C.tol_position, C.tol_orientation = length_unit, tol_position, tol_orientation
    C.limit_tol, C.same_tol, C.every = limit_tol, same_tol, every
    cdef cnp.ndarray q_out = new_array(2, N, n, 0, cnp.NPY_DOUBLE)
    cdef cnp.ndarray ok_out = new_array(1, N, 0, 0, cnp.NPY_BOOL)
    cdef cnp.ndarray ep_out = new_array(1, N, 0, 0, cnp.NPY_DOUBLE)
    cdef cnp.ndarray eo_out = new_array(1, N, 0, 0, cnp.NPY_DOUBLE)
    C.qo = <double*>cnp.PyArray_DATA(q_out)
    C.ok = <unsigned char*>cnp.PyArray_DATA(ok_out)
    C.ep = <double*>cnp.PyArray_DATA(ep_out)
    C.eo = <double*>cnp.PyArray_DATA(eo_out)
    cdef double* unit = <double*>malloc(max(n, 1) * sizeof(double))
    # with every: per target its distinct verified rows (N, S) and their count (N,)
    cdef Py_ssize_t* kept = <Py_ssize_t*>malloc((max(N * S, 1) + max(N, 1)) * sizeof(Py_ssize_t)) if every else NULL
    if unit == NULL or (every and kept == NULL):
        free(unit)
        free(kept)
        raise MemoryError()
    for j in range(n):
        unit[j] = 1.0 if chain.rev[j] else length_unit
    C.unit, C.kept, C.m = unit, kept, (kept + max(N * S, 1) if every else NULL)
    cdef Py_ssize_t failed = 0, short = 0, size = scratch_bytes(S, n, every)
    cdef int nt = batch_threads(threads, N, MIN_TARGETS_PER_THREAD)
    cdef char* scratch = NULL
    cdef list sols = [None] * N if every else None
    try:
        if nt <= 1:     # no OpenMP region: entering one costs as much as checking a target
            scratch = <char*>malloc(size)
            if scratch == NULL:
                raise MemoryError()
            with nogil:
                for k in range(N):
                    failed += check_target(&C, k, scratch)
            free(scratch)
        else:
            with nogil, parallel(num_threads=nt):
                scratch = <char*>malloc(size)       # each thread's own
                for k in prange(N, schedule="dynamic", chunksize=TARGETS_PER_CHUNK):
                    if scratch == NULL:
                        short += 1    # a reduction: any thread that ran out of memory counts
                        continue
                    failed += check_target(&C, k, scratch)
                free(scratch)
            if short:
                raise MemoryError()
        if every:
            for k in range(N):
                sols[k] = rows_array(C.q + k * S * n, n, kept + k * S, C.m[k])
    finally:
        free(unit)
        free(kept)
    return q_out, ok_out, sols, ep_out, eo_out, failed
