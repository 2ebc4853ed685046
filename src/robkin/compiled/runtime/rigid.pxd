# cython: language_level=3
"""Is a 4x4 matrix an exact rigid transform: the one test behind ``Robot`` construction
(``checks.check_poses``), IK targets (``kinematics.pose_error.check_targets``) and the closed-form
kernels' single-target entry. No dependency on the FK core, so validating a Robot loads nothing else.
"""

from libc.math cimport fabs, isfinite


cdef inline bint exact_pose(const double* T) noexcept nogil:
    """Whether T (4x4 row-major) is finite, has the last row exactly [0, 0, 0, 1] and a rotation block
    orthonormal to 1e-12 (max |R^T R - I|) with det > 0.

    Rotations produced by products of exact rotations are orthonormal to ~1e-15; anything farther goes
    through the documented checks (projection or refusal) of ``robot.check_pose``.
    """
    cdef int i, j, r
    cdef double s
    if not (T[12] == 0.0 and T[13] == 0.0 and T[14] == 0.0 and T[15] == 1.0):
        return False
    for i in range(12):
        if not isfinite(T[i]):
            return False
    for i in range(3):
        for j in range(i, 3):
            s = 0.0
            for r in range(3):
                s += T[4 * r + i] * T[4 * r + j]
            if fabs(s - (1.0 if i == j else 0.0)) > 1e-12:
                return False
    return (T[0] * (T[5] * T[10] - T[6] * T[9]) - T[1] * (T[4] * T[10] - T[6] * T[8])
            + T[2] * (T[4] * T[9] - T[5] * T[8])) > 0.0
