# cython: language_level=3
"""Pose checks as ``cdef inline`` functions: is a target an exact pose, and how far is the tool from it.

(The acceptance test of IK targets, ``exact_pose``, is in ``rigid.pxd``.) ``tool_errors`` is the forward-kinematics check of one
configuration, used by ``lm.pose_errors`` (the check of every IK answer); the closed-form branch
choice (``nearest.pxd``) walks its branches as one block of ``fk.pxd`` (the same bits as one walk each)
and measures them with the same ``tool_pose_errors``, so all judge a solution by the same walk and the
same residual.
"""

from libc.math cimport sqrt, isfinite, INFINITY
from robkin.compiled.chain.fk cimport walk_tool
from robkin.compiled.runtime.linalg cimport rot_log


cdef inline bint finite_row(const double* q, int n) noexcept nogil:
    """Whether every entry of q (n,) is finite."""
    cdef int j
    for j in range(n):
        if not isfinite(q[j]):
            return False
    return True


cdef inline void tool_pose_errors(const double* T, const double* D, const double* msk, double* ep,
                             double* eo) noexcept nogil:
    """ep, eo = masked |p_d - p| (length units) and |log(R_d R^T)| (radians) of the tool pose T towards
    the target D (both 4x4 row-major); the 0/1 ``msk`` (6,) selects components."""
    cdef double R[9]
    cdef double e[6]
    cdef int i, j
    for i in range(3):
        e[i] = (D[4 * i + 3] - T[4 * i + 3]) * msk[i]
        for j in range(3):
            R[3 * i + j] = D[4 * i] * T[4 * j] + D[4 * i + 1] * T[4 * j + 1] + D[4 * i + 2] * T[4 * j + 2]
    rot_log(R, e + 3)
    for i in range(3, 6):
        e[i] *= msk[i]
    ep[0] = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
    eo[0] = sqrt(e[3] * e[3] + e[4] * e[4] + e[5] * e[5])


cdef inline void tool_errors(const double* L, const unsigned char* rev, int n, const double* q,
                             const double* D, const double* msk, double* ep, double* eo) noexcept nogil:
    """``tool_pose_errors`` of the tool at q (n,) (one walk of ``fk.pxd``) towards the target D (4x4
    row-major); inf if q is not finite."""
    cdef double T[16]
    if not finite_row(q, n):
        ep[0] = INFINITY
        eo[0] = INFINITY
        return
    walk_tool(L, rev, n, q, T)
    tool_pose_errors(T, D, msk, ep, eo)
