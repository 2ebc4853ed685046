# The stages of ``dh_from_robot(s)`` / ``mdh_from_robot(s)`` after the frame placement, one robot at a
# time, included by frames.pyx (see frame_geometry.pxi for why an include): the flip of the joint
# frames, the rounding of near-round values (``representations.rounding.snap_many``), the residual tool
# (``link_table.residual_tool``) and the FK self-check (``link_table.sample_configurations``,
# ``pose_difference``). Uses dh_placement.pxi and the compiled FK walk (``fk.pxd``).
#
# These stages were NumPy code; the tables they make must stay the same bits, so the arithmetic here is
# NumPy's, operation for operation: element-wise products and sums in the order the NumPy expressions
# evaluate them, and the two kinds of 4x4 / 3x3 matrix product NumPy's ``@`` does (through its BLAS):
# a matrix-matrix product sums each entry as a chain of fused multiply-adds in k order
# (``numpy_order.gemm_fma``); a matrix-vector product sums plain products in k order (``relative_np``). These are
# what the x86-64 OpenBLAS that NumPy ships computes on FMA-capable machines; the tests
# in ``tests/test_convert_stages.py`` check every stage against the NumPy functions it replaces.

from libc.math cimport fma, rint, isfinite, INFINITY
from robkin.compiled.runtime.numpy_order cimport gemm_fma, norm3_np

#: rounding.SNAP_WINDOW, rounding.SNAP_BUDGET (their reasons are stated there)
cdef double SNAP_WINDOW = _SNAP_WINDOW
cdef double SNAP_BUDGET = _SNAP_BUDGET
cdef double QUARTER = M_PI / 2


cdef inline void relative_np(const double* P, const double* F, double* T) noexcept nogil:
    """T = P^-1 F for rigid poses, as ``frames.relative_pose`` computes it in NumPy: R^T F_R as a
    matrix product (fused multiply-adds), R^T (o_F - o_P) as a matrix-vector product (plain sums)."""
    cdef double w[3]
    cdef double s
    cdef int i, j
    for i in range(3):
        w[i] = F[4 * i + 3] - P[4 * i + 3]
    for i in range(3):
        for j in range(3):
            s = P[i] * F[j]
            s = fma(P[4 + i], F[4 + j], s)
            T[4 * i + j] = fma(P[8 + i], F[8 + j], s)
        T[4 * i + 3] = (P[i] * w[0] + P[4 + i] * w[1]) + P[8 + i] * w[2]
    T[12], T[13], T[14], T[15] = 0.0, 0.0, 0.0, 1.0


cdef inline bint identity_np(const double* T, double scale) noexcept nogil:
    """``frames.identity_mask`` with tol = KEEP_TOL."""
    cdef int i, j
    for i in range(3):
        for j in range(3):
            if not (fabs(T[4 * i + j] - (1.0 if i == j else 0.0)) <= KEEP_TOL):
                return False
        if not (fabs(T[4 * i + 3]) <= KEEP_TOL * scale):
            return False
    return True


cdef void snap_c(double* rows, Py_ssize_t n, const double* trav, const double* tool, double scale,
                 double* scratch) noexcept nogil:
    """``rounding.snap_many`` for one robot: rows (n, 4) in place; ``trav`` (n,) the joints' travel,
    ``tool`` the pose after the last row; ``scratch`` room for 4 * 4 * n doubles."""
    cdef Py_ssize_t N = 4 * n, i, c, p, q
    cdef double* target = scratch
    cdef double* cost = scratch + N
    cdef double* order = scratch + 2 * N   # candidate indices (as doubles), cheapest first
    cdef double* lever = scratch + 3 * N   # per row: the rotation lever (``_levers``)
    cdef double acc = norm3_np(tool[3], tool[7], tool[11]), off, window, lv, spent
    cdef Py_ssize_t count = 0
    # levers: the tool's offset, then |a| + |d| + travel summed from the last row backwards
    for i in range(n - 1, -1, -1):
        acc = acc + ((fabs(rows[4 * i]) + fabs(rows[4 * i + 1])) + trav[i])
        lever[i] = acc if acc > scale else scale   # np.maximum(levers, scale); acc is never NaN
    for p in range(N):
        c = p % 4
        i = p // 4
        if c < 2:
            target[p] = 0.0
            window = SNAP_WINDOW * scale
            lv = 1.0
        else:
            target[p] = QUARTER * rint(rows[p] / QUARTER) + 0.0
            window = SNAP_WINDOW
            lv = lever[i]
        off = fabs(rows[p] - target[p])
        if rows[p] != target[p] and off <= window and isfinite(lv):
            cost[p] = off * lv
            # insertion into the cheapest-first order; equal costs keep row-major order (stable)
            q = count
            while q > 0 and cost[<Py_ssize_t>order[q - 1]] > cost[p]:
                order[q] = order[q - 1]
                q -= 1
            order[q] = <double>p
            count += 1
    spent = 0.0
    for q in range(count):
        p = <Py_ssize_t>order[q]
        spent = spent + cost[p]
        if spent < SNAP_BUDGET * scale:
            rows[p] = target[p]
    for p in range(N):   # pi/2 multiples that came out as -pi are written as +pi (tidy_angle)
        if p % 4 >= 2 and rows[p] == -M_PI:
            rows[p] = M_PI


cdef void table_of_robot(bint modified, const double* frames, Py_ssize_t n, const unsigned char* flip,
                         const double* flip_x, const double* trav, double scale, bint keep, bint snap,
                         double* rows, double* tool, double* scratch) noexcept nogil:
    """One robot's rows (n, 4) and residual tool (its base is frame {0}, ``scratch[32 n:][:16]``):
    the flip of its joint frames (``placement.joint_frames``), the DH or MDH chain, the rounding (when
    ``snap``) and the residual tool. ``scratch``: room for 48 * n + 16 doubles."""
    cdef double* cand = scratch
    cdef double* F = scratch + 32 * n
    cdef double T[16]
    cdef double U[16]
    cdef double A[16]
    cdef Py_ssize_t i
    cdef const double* tool_pose = frames + 16 * n
    for i in range(n):
        if flip[i]:
            gemm_fma(frames + 16 * i, flip_x, cand + 16 * i)
        else:
            tf_copy(frames + 16 * i, cand + 16 * i)
    if modified:
        mdh_chain(cand, n, scale, keep, F, rows)
    else:
        dh_chain(cand, n, tool_pose, scale, keep, F, rows)
    if snap:
        relative_np(F + 16 * n, tool_pose, T)
        snap_c(rows, n, trav, T, scale, scratch + 16 * n)
    # the residual tool: base A_1(0) ... A_n(0) composed from the rows as written, then what remains
    tf_copy(F, T)
    for i in range(n):
        if modified:
            mdh_matrix_c(rows + 4 * i, A)
        else:
            dh_matrix_c(rows + 4 * i, A)
        gemm_fma(T, A, U)
        tf_copy(U, T)
    relative_np(T, tool_pose, tool)
    if identity_np(tool, scale):
        tf_identity(tool)


cdef void check_of_table(bint modified, const double* base, const double* rows, const double* tool,
                         const double* L, Py_ssize_t n, const unsigned char* rev, const double* sign,
                         const double* limits, double scale, const double* U, Py_ssize_t samples,
                         double* Q, double* poses, double* err, double* length) noexcept nogil:
    """The FK self-check of one table: its largest pose difference from the robot (``err``, length
    units) over q = 0 and ``samples`` configurations scaled from the unit sample U (samples, n)
    (``link_table.sample_configurations``), and its longest length (``length``: the largest |a|, |d|
    or base / tool offset). ``Q`` room for (samples + 1) * n, ``poses`` for 32 * (samples + 1)."""
    cdef Py_ssize_t m = samples + 1, c, i
    cdef double span, lo, hi, q, e, pos, rot, dx, dy, dz
    cdef double row[4]
    cdef double A[16]
    cdef double T[16]
    cdef double V[16]
    cdef double* robot_fk = poses + 16 * m
    for i in range(n):
        span = M_PI if rev[i] else scale
        lo = max(limits[2 * i], -span) if isfinite(limits[2 * i]) else -span
        hi = min(limits[2 * i + 1], span) if isfinite(limits[2 * i + 1]) else span
        Q[i] = 0.0
        for c in range(samples):
            Q[n * (c + 1) + i] = lo + U[n * c + i] * (hi - lo)
    tool_poses(L, rev, <int>n, Q, m, robot_fk)
    err[0] = -INFINITY
    for c in range(m):   # ``tables_fk``: base A_1(q_1) ... A_n(q_n) tool, compiled products
        tf_copy(base, T)
        for i in range(n):
            row[0], row[1], row[2], row[3] = rows[4 * i], rows[4 * i + 1], rows[4 * i + 2], rows[4 * i + 3]
            q = sign[i] * Q[n * c + i]
            if rev[i]:
                row[3] = row[3] + q
            else:
                row[1] = row[1] + q
            if modified:
                mdh_matrix_c(row, A)
            else:
                dh_matrix_c(row, A)
            tf_mul(T, A, V)
            tf_copy(V, T)
        tf_mul(T, tool, poses + 16 * c)
        # ``pose_difference``: position difference plus the largest rotation entry's times the scale
        dx = poses[16 * c + 3] - robot_fk[16 * c + 3]
        dy = poses[16 * c + 7] - robot_fk[16 * c + 7]
        dz = poses[16 * c + 11] - robot_fk[16 * c + 11]
        pos = norm3_np(dx, dy, dz)
        rot = 0.0
        for i in range(12):
            if i % 4 != 3:
                e = fabs(poses[16 * c + i] - robot_fk[16 * c + i])
                if e > rot or e != e:
                    rot = e
        e = pos + rot * scale
        if e > err[0] or e != e:
            err[0] = e
    length[0] = max(norm3_np(base[3], base[7], base[11]), norm3_np(tool[3], tool[7], tool[11]))
    for i in range(n):
        length[0] = max(length[0], max(fabs(rows[4 * i]), fabs(rows[4 * i + 1])))
