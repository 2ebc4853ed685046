# cython: language_level=3
"""Newton polish of closed-form candidates on the exact forward kinematics, as a ``cdef inline`` function
(shared by ``closed_form_general6r`` and ``closed_form_pieper``)."""

from libc.math cimport sqrt, INFINITY
from robkin.compiled.runtime.dense cimport cholesky_solve
from robkin.compiled.chain.fk cimport BLOCK, walk_block
from robkin.compiled.runtime.linalg cimport rot_log

cdef enum:
    NEWTON_STEPS = 8

#: Newton on the exact forward kinematics: at most NEWTON_STEPS steps, stopping once the residual
#: (position / robot size + orientation, radians) is below NEWTON_DONE (a few ulps of a unit pose);
#: a candidate whose residual stays above CANDIDATE_TOL (1e-6: far above the 1e-9 the FK check of
#: ``nearest.pxd`` demands after polishing, far below any real miss) is dropped before that check.
cdef extern from *:
    """
    #define RK_NEWTON_DONE 1e-15
    #define RK_CANDIDATE_TOL 1e-6
    """
    double NEWTON_DONE "RK_NEWTON_DONE"
    double CANDIDATE_TOL "RK_CANDIDATE_TOL"


cdef inline double newton_polish(const double* L, const unsigned char* rev, double scale, const double* Rd,
                                 const double* pd, double* q, double* work) noexcept nogil:
    """Newton steps on the exact forward kinematics of a 6-joint chain (``fk.pxd``'s L, rev) from q (6,)
    towards the target (R_d, p_d); returns the final residual |dp| / scale + |dw| (q updated in place,
    never to a worse residual). work: 6 doubles of scratch."""
    cdef double P[12 * BLOCK]
    cdef double Z[36]
    cdef double e[6]
    cdef double J[36]
    cdef double A[36]
    cdef double R[9]
    cdef double p[3]
    cdef double d[3]
    cdef double zc[3]
    cdef double r, best = INFINITY
    cdef int it, i, j, k
    for it in range(NEWTON_STEPS + 1):
        walk_block(L, rev, 6, q, 1, P, NULL, Z, 1, NULL, 0)
        for i in range(3):
            p[i] = P[BLOCK * (4 * i + 3)]
            e[i] = pd[i] - p[i]
            for j in range(3):
                R[3 * i + j] = (Rd[3 * i] * P[BLOCK * (4 * j)] + Rd[3 * i + 1] * P[BLOCK * (4 * j + 1)]
                                + Rd[3 * i + 2] * P[BLOCK * (4 * j + 2)])
        rot_log(R, e + 3)
        r = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) / scale \
            + sqrt(e[3] * e[3] + e[4] * e[4] + e[5] * e[5])
        if not (r < best):       # no progress (or NaN): the previous q stays
            if it > 0:
                for i in range(6):
                    q[i] -= work[i]
            return best
        best = r
        if r < NEWTON_DONE or it == NEWTON_STEPS:
            return r
        # J columns: [z_i x (p - p_i); z_i] (base frame), lengths over the robot size, and the
        # residual in the same units
        for i in range(3):
            e[i] = (pd[i] - p[i]) / scale
        for i in range(6):
            for k in range(3):
                d[k] = (p[k] - Z[6 * k + i]) / scale
                zc[k] = Z[6 * (k + 3) + i]
            J[6 * 0 + i] = zc[1] * d[2] - zc[2] * d[1]
            J[6 * 1 + i] = zc[2] * d[0] - zc[0] * d[2]
            J[6 * 2 + i] = zc[0] * d[1] - zc[1] * d[0]
            J[6 * 3 + i] = zc[0]
            J[6 * 4 + i] = zc[1]
            J[6 * 5 + i] = zc[2]
        # (J^T J + mu I) dq = J^T e; mu: 1e-14 keeps a singular J solvable without biasing a
        # regular one (its squared singular values are O(1) in these units)
        for i in range(6):
            work[i] = 0.0
            for k in range(6):
                work[i] += J[6 * k + i] * e[k]
            for j in range(6):
                A[6 * i + j] = 0.0
                for k in range(6):
                    A[6 * i + j] += J[6 * k + i] * J[6 * k + j]
            A[6 * i + i] += 1e-14
        if not cholesky_solve(A, work, 6):
            return best
        for i in range(6):
            q[i] += work[i]
    return best
