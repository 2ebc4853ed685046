# DH / modified DH frame placement, included by frames.pyx (see frame_geometry.pxi for why an include):
# the canonical frame rules (``robkin.representations.frames``), the parameters between two frames,
# the DH / MDH link matrices, and the frame chains of ``dh_from_robot`` / ``mdh_from_robot``. Uses the
# line geometry of frame_geometry.pxi and the tolerances KEEP_TOL, TIE_TOL, NOISE_TILT, FAR of frames.pyx.


cdef bint satisfies(const double* frame, const double* p_other, const double* u_other,
                    double scale, double tol) noexcept nogil:
    """Does the frame's x axis cross the line (p_other, u_other) at a right angle (to tol, and
    tol * scale for the distance)?"""
    cdef double o[3]
    cdef double x[3]
    cdef double c1[3]
    cdef double c2[3]
    col(frame, 3, o)
    col(frame, 0, x)
    if fabs(dot3(x, u_other)) > tol:
        return False
    if sin_between(x, u_other) < ANGLE_TOL:  # x along the other line: cannot cross it
        return False
    return closest(o, x, p_other, u_other, c1, c2) <= tol * scale


cdef inline void choose_sign(double* x, const double* x_pref, const double* y_pref) noexcept nogil:
    """x or -x, whichever keeps |theta| <= pi/2 from x_pref (ties: theta = +pi/2 towards y_pref)."""
    cdef double c = dot3(x, x_pref)
    cdef bint flip
    if fabs(c) > TIE_TOL:
        flip = not (c > 0)
    else:
        flip = not (dot3(x, y_pref) >= 0)
    if flip:
        x[0], x[1], x[2] = -x[0], -x[1], -x[2]


cdef void normal_frame_c(const double* p_a, const double* u_a, const double* p_b, const double* u_b,
                         bint on_b, const double* prev, double scale, const double* keep,
                         double* out) noexcept nogil:
    """Frame on line A (on_b false) or B whose x is the common normal from A to B; ``keep`` (or NULL)
    is returned when it satisfies the convention (``frames.common_normal_frame``)."""
    cdef const double* u_self = u_b if on_b else u_a
    cdef const double* u_other = u_a if on_b else u_b
    cdef const double* p_other = p_a if on_b else p_b
    if keep != NULL and satisfies(keep, p_other, u_other, scale, KEEP_TOL):
        tf_copy(keep, out)
        return
    cdef double x_prev[3]
    cdef double o_prev[3]
    cdef double anchor[3]
    cdef double y_ref[3]
    cdef double x[3]
    cdef double f[3]
    cdef double c1[3]
    cdef double c2[3]
    cdef double dist, c
    cdef int i
    col(prev, 0, x_prev)
    col(prev, 3, o_prev)
    if on_b:  # where the previous frame meets line A: its origin (DH), or where its x crosses A (MDH)
        foot(o_prev, p_a, u_a, anchor)
    else:
        x_line_meet(prev, p_a, u_a, anchor)
    cross3(u_a, x_prev, y_ref)
    cdef Relation rel = classify(p_a, u_a, p_b, u_b, scale)
    if rel == PARALLEL or rel == ANTI_PARALLEL:
        foot(anchor, p_b, u_b, f)
        for i in range(3):
            x[i] = f[i] - anchor[i]
        dist = norm3(x)
        # measured from the anchor the lines may still meet to rounding: then they are coincident
        if dist > LENGTH_TOL * scale:
            for i in range(3):
                x[i] = x[i] / dist  # unit before the sign test (its tie margin is on a cosine)
            choose_sign(x, x_prev, y_ref)
            if on_b:
                from_zx(f, u_self, x, out)
            else:
                from_zx(anchor, u_self, x, out)
            return
        rel = COINCIDENT
    if rel == COINCIDENT or rel == ANTI_COINCIDENT:
        c = dot3(x_prev, u_self)
        for i in range(3):
            x[i] = x_prev[i] - c * u_self[i]
        if norm3(x) < 1e-6:  # prev x along the axis (cannot happen for a valid chain)
            perpendicular(u_self, x)
        if on_b:
            foot(anchor, p_b, u_b, f)
            from_zx(f, u_self, x, out)
        else:
            from_zx(anchor, u_self, x, out)
        return
    closest(p_a, u_a, p_b, u_b, c1, c2)
    cross3(u_a, u_b, x)
    dist = norm3(x)
    for i in range(3):
        x[i] = x[i] / dist
    choose_sign(x, x_prev, y_ref)
    if on_b:
        from_zx(c2, u_self, x, out)
    else:
        from_zx(c1, u_self, x, out)


cdef inline double tidy(double angle) noexcept nogil:
    """An angle in (-pi, pi]: within 1e-12 of -pi becomes +pi, -0.0 becomes 0 (``frames.tidy_angle``)."""
    if angle <= -M_PI + 1e-12:
        return M_PI
    return angle + 0.0


cdef void relative(const double* prev, const double* frame, double* T) noexcept nogil:
    """T = prev^-1 frame for rigid poses (R^T)."""
    cdef int i, j
    cdef double w[3]
    for i in range(3):
        w[i] = frame[4 * i + 3] - prev[4 * i + 3]
    for i in range(3):
        for j in range(3):
            T[4 * i + j] = prev[i] * frame[j] + prev[4 + i] * frame[4 + j] + prev[8 + i] * frame[8 + j]
        T[4 * i + 3] = prev[i] * w[0] + prev[4 + i] * w[1] + prev[8 + i] * w[2]
    T[12], T[13], T[14], T[15] = 0.0, 0.0, 0.0, 1.0


cdef void dh_params_c(const double* prev, const double* frame, double* row) noexcept nogil:
    """(a, d, alpha, theta) with prev^-1 frame = Rz(theta) Tz(d) Tx(a) Rx(alpha)."""
    cdef double T[16]
    relative(prev, frame, T)
    cdef double theta = atan2(T[4], T[0])
    cdef double alpha = atan2(T[9], T[10])
    row[0] = T[3] * cos(theta) + T[7] * sin(theta)
    row[1] = T[11]
    row[2] = tidy(alpha)
    row[3] = tidy(theta)


cdef void mdh_params_c(const double* prev, const double* frame, double* row) noexcept nogil:
    """(a, d, alpha, theta) with prev^-1 frame = Rx(alpha) Tx(a) Rz(theta) Tz(d)."""
    cdef double T[16]
    relative(prev, frame, T)
    cdef double alpha = atan2(-T[6], T[10])
    cdef double theta = atan2(-T[1], T[0])
    row[0] = T[3]
    row[1] = -T[7] * sin(alpha) + T[11] * cos(alpha)
    row[2] = tidy(alpha)
    row[3] = tidy(theta)


cdef void dh_matrix_c(const double* row, double* A) noexcept nogil:
    """Rz(theta) Tz(d) Tx(a) Rx(alpha) for row (a, d, alpha, theta)."""
    cdef double ct = cos(row[3]), st = sin(row[3]), ca = cos(row[2]), sa = sin(row[2])
    A[0], A[1], A[2], A[3] = ct, -st * ca, st * sa, row[0] * ct
    A[4], A[5], A[6], A[7] = st, ct * ca, -ct * sa, row[0] * st
    A[8], A[9], A[10], A[11] = 0.0, sa, ca, row[1]
    A[12], A[13], A[14], A[15] = 0.0, 0.0, 0.0, 1.0


cdef void mdh_matrix_c(const double* row, double* A) noexcept nogil:
    """Rx(alpha) Tx(a) Rz(theta) Tz(d) for row (a, d, alpha, theta)."""
    cdef double ct = cos(row[3]), st = sin(row[3]), ca = cos(row[2]), sa = sin(row[2])
    A[0], A[1], A[2], A[3] = ct, -st, 0.0, row[0]
    A[4], A[5], A[6], A[7] = st * ca, ct * ca, -sa, -sa * row[1]
    A[8], A[9], A[10], A[11] = st * sa, ct * sa, ca, ca * row[1]
    A[12], A[13], A[14], A[15] = 0.0, 0.0, 0.0, 1.0


cdef void approx_dh_c(const double* prev, const double* target, double* row) noexcept nogil:
    """The conversion paper's last-row rule (``frames.approx_dh_params``), ties to + by KEEP_TOL."""
    cdef double o0[3]
    cdef double x0[3]
    cdef double y0[3]
    cdef double z0[3]
    cdef double o1[3]
    cdef double x1[3]
    cdef double y1[3]
    cdef double z1[3]
    cdef double w[3]
    col(prev, 3, o0)
    col(prev, 0, x0)
    col(prev, 1, y0)
    col(prev, 2, z0)
    col(target, 3, o1)
    col(target, 0, x1)
    col(target, 1, y1)
    col(target, 2, z1)
    cdef int i
    for i in range(3):
        w[i] = o1[i] - o0[i]
    cdef double reach = max(norm3(w), max(norm3(o0), norm3(o1)))
    cdef double theta = atan2(sin_between(x0, x1), dot3(x0, x1))
    if dot3(y0, x1) < -KEEP_TOL:
        theta = -theta
    cdef double alpha = atan2(sin_between(z0, z1), dot3(z0, z1))
    if dot3(y1, z0) < -KEEP_TOL:
        alpha = -alpha
    cdef double d = line_distance(o0, x0, o1, x1)
    if dot3(w, z0) < -KEEP_TOL * reach:
        d = -d
    cdef double a = line_distance(o0, z0, o1, z1)
    if dot3(w, x1) < -KEEP_TOL * reach:
        a = -a
    row[0], row[1], row[2], row[3] = a, d, alpha, theta


cdef void dh_chain(const double* cand, Py_ssize_t n, const double* tool, double scale, bint keep,
                   double* F, double* rows) noexcept nogil:
    """DH frames {0}..{n-1} and the last frame {n} into F (n+1 poses) and the rows (n, 4) between
    them, from the flip-adjusted joint frames ``cand`` (n poses) and the tool pose
    (``representations.dh.dh_frames``)."""
    cdef double I[16]
    cdef double pa[3]
    cdef double ua[3]
    cdef double pb[3]
    cdef double ub[3]
    cdef double row[4]
    cdef double A[16]
    cdef const double* prev = I
    cdef Py_ssize_t i
    cdef double ref[16]
    tf_identity(I)
    for i in range(n):
        line_of(prev, pa, ua)
        line_of(cand + 16 * i, pb, ub)
        normal_frame_c(pa, ua, pb, ub, True, prev, scale, cand + 16 * i if keep else NULL, F + 16 * i)
        if i == 0 and tilted_base(cand, F, scale, False, ref):
            # joint 1 nearly parallel to the base z axis: frame {0} on joint 1's axis below the base
            # origin, from the base turned onto that axis (the modified DH rule), not where the common
            # normal lies ~offset / tilt away
            line_of(ref, pa, ua)
            normal_frame_c(pa, ua, pb, ub, True, ref, scale, cand if keep else NULL, F)
        prev = F + 16 * i
    line_of(prev, pa, ua)
    if satisfies(tool, pa, ua, scale, KEEP_TOL):
        tf_copy(tool, F + 16 * n)
    else:
        approx_dh_c(prev, tool, row)
        dh_matrix_c(row, A)
        tf_mul(prev, A, F + 16 * n)
    for i in range(n):
        dh_params_c(F + 16 * i, F + 16 * (i + 1), rows + 4 * i)


cdef bint tilted_base(const double* joint1, const double* frame0, double scale, bint parallel_too,
                      double* ref) noexcept nogil:
    """For a joint 1 axis nearly parallel to the base z axis whose frame {0} (``frame0``, placed by the
    common-normal rule) lies more than FAR robot sizes away (or, with ``parallel_too``, whose axis is
    parallel to within ANGLE_TOL): the base turned by the smallest rotation taking z onto joint 1's
    axis, moved onto that axis (into ``ref``), and True; else False. Shared by DH and modified DH."""
    cdef double ez[3]
    cdef double p[3]
    cdef double u[3]
    cdef double w[3]
    cdef double v[3]
    cdef double K[9]
    cdef double c, t
    cdef int i, j
    ez[0], ez[1], ez[2] = 0.0, 0.0, 1.0
    line_of(joint1, p, u)
    cdef double s = sin_between(ez, u)
    cdef double r = sqrt(frame0[3] * frame0[3] + frame0[7] * frame0[7] + frame0[11] * frame0[11])
    if not (NOISE_TILT < s and ((parallel_too and s < ANGLE_TOL) or r > FAR * scale)):
        return False
    # an anti-parallel axis is taken as the line along -u, so frame {0}'s z stays near the base z
    for i in range(3):
        w[i] = u[i] if u[2] > 0 else -u[i]
    cross3(ez, w, v)
    c = dot3(ez, w)
    K[0], K[1], K[2] = 0.0, -v[2], v[1]
    K[3], K[4], K[5] = v[2], 0.0, -v[0]
    K[6], K[7], K[8] = -v[1], v[0], 0.0
    t = dot3(p, w)
    for i in range(3):
        for j in range(3):
            ref[4 * i + j] = (1.0 if i == j else 0.0) + K[3 * i + j] + (
                K[3 * i] * K[j] + K[3 * i + 1] * K[3 + j] + K[3 * i + 2] * K[6 + j]) / (1.0 + c)
        ref[4 * i + 3] = p[i] - t * w[i]
    ref[12], ref[13], ref[14], ref[15] = 0.0, 0.0, 0.0, 1.0
    return True


cdef void mdh_base(const double* joint1, double scale, double* out) noexcept nogil:
    """Frame {0} of a modified DH table (``representations.mdh._base_frame``): on the base z axis with
    x towards joint 1's axis, or, for a joint 1 axis nearly parallel to that axis, on joint 1's axis
    turned from the base by the smallest rotation taking z onto it (``tilted_base``)."""
    cdef double I[16]
    cdef double zero[3]
    cdef double ez[3]
    cdef double p[3]
    cdef double u[3]
    cdef double v[3]
    cdef double ref[16]
    cdef int i
    tf_identity(I)
    zero[0], zero[1], zero[2] = 0.0, 0.0, 0.0
    ez[0], ez[1], ez[2] = 0.0, 0.0, 1.0
    line_of(joint1, p, u)
    normal_frame_c(zero, ez, p, u, False, I, scale, I, out)
    if not tilted_base(joint1, out, scale, True, ref):
        return
    for i in range(3):
        v[i] = ref[4 * i + 3]
        ez[i] = u[i] if u[2] > 0 else -u[i]  # the axis tilted_base turned z onto
    normal_frame_c(v, ez, p, u, False, ref, scale, ref, out)


cdef void mdh_chain(const double* cand, Py_ssize_t n, double scale, bint keep,
                    double* M, double* rows) noexcept nogil:
    """Modified DH frames {0}..{n} into M (n+1 poses) and the rows (n, 4) between them, from the
    flip-adjusted joint frames ``cand`` (n poses) (``representations.mdh.mdh_frames``)."""
    cdef double pa[3]
    cdef double ua[3]
    cdef double pb[3]
    cdef double ub[3]
    cdef double x[3]
    cdef double o[3]
    cdef Py_ssize_t i
    mdh_base(cand, scale, M)
    for i in range(n - 1):
        line_of(cand + 16 * i, pa, ua)
        line_of(cand + 16 * (i + 1), pb, ub)
        normal_frame_c(pa, ua, pb, ub, False, M + 16 * i, scale, cand + 16 * i if keep else NULL,
                       M + 16 * (i + 1))
    if keep:
        tf_copy(cand + 16 * (n - 1), M + 16 * n)
    else:
        # frame {n}: where frame {n-1}'s x line meets joint n's axis, with the same x (its x is free)
        line_of(cand + 16 * (n - 1), pa, ua)
        x_line_meet(M + 16 * (n - 1), pa, ua, o)
        col(M + 16 * (n - 1), 0, x)
        from_zx(o, ua, x, M + 16 * n)
    for i in range(n):
        mdh_params_c(M + 16 * i, M + 16 * (i + 1), rows + 4 * i)
