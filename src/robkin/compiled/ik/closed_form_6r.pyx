"""Compiled closed-form IK of the two 6R families (the kernels behind ``kinematics.analytic6r``).

Each kernel is built once per robot from the geometry the Python detector found (joint axes z_i and
points c_i at q = 0, the tool pose M, the plane of the parallel axes) and solves targets one by one
in C (``solve_one``; the batch loop and the single-target entry are the base class's,
``closed_form_kernel.ClosedFormKernel``): all 8 branches, wrapped into the joint limits, each marked
valid or not, and per target a code saying which step failed first. The Python side only validates,
and turns codes into messages.

Outcome codes per target (``code``):

0 a valid branch exists; 1 singular target, no branch with the preferred free joint (``uncertain``);
2 joint 1 cannot bring the wrist point into the plane of the parallel axes; 3 (spherical wrist) the
wrist centre is out of the reach of joints 2-3 / (three parallel) the last axis cannot point that way;
4 (spherical wrist) the wrist cannot reach the orientation / (three parallel) axis 4 is out of the reach
of joints 2-3; 5 geometric solutions exist but violate the joint limits. ``detail`` holds the distance
the reach messages quote.
"""

import numpy as np

cimport numpy as cnp
from libc.math cimport hypot, INFINITY
from robkin.compiled.ik.closed_form_kernel cimport ClosedFormKernel
from robkin.compiled.chain.fk cimport Chain
from robkin.compiled.runtime.linalg cimport cross3, dot3, mat3_mul, mat3_vec, mat3T_vec, rodrigues
from robkin.compiled.ik.subproblems cimport (angle_about, cos_sin_equation, mat3T_mul, planar_two_link,
                                          TwoLink, two_axes, two_link, wrap_branches)

cnp.import_array()

#: Within this (relative) distance of a singularity - the wrist point on axis 1, axis 6 along the
#: parallel axes - the closed form's angles are only known to ~sqrt(eps) (arccos near +-1): a target
#: left without a branch there is flagged uncertain (``ik`` retries it numerically), not unreachable.
NEAR_SINGULAR = 1e-6
cdef double _NEAR_SINGULAR = NEAR_SINGULAR

#: The wrist-singular search of the three-parallel kernel: candidate angles phi_ref +- k degrees,
#: k = 0..180 (any reaching phi is an exact solution; 1 degree finds the reaching arcs of real arms).
cdef int GRID_STEPS = 180
cdef double DEG = 0.017453292519943295


cdef inline signed char _outcome(int wrapped, bint uncertain, bint shoulder_ok,
                                 bint second_ok) noexcept nogil:
    """The outcome code (see the module docstring) from ``wrap_branches``'s result and the steps' flags:
    the shoulder equation, and the second step (elbow reach / wrist axis) for some shoulder."""
    if wrapped == 0:
        return 0
    if uncertain:
        return 1
    if not shoulder_ok:
        return 2
    if not second_ok:
        return 3
    return 4 if wrapped == 1 else 5


cdef void _copy3(object src, double* dst):
    cdef int i
    for i in range(3):
        dst[i] = float(src[i])


cdef void _copy33(object src, double* dst):
    cdef int i, j
    for i in range(3):
        for j in range(3):
            dst[3 * i + j] = float(src[i][j])


cdef class _Kernel6R(ClosedFormKernel):
    """Geometry shared by both families: axes, points, tool, the plane of the parallel axes."""

    cdef double z[6][3]
    cdef double c[6][3]
    cdef double w_tool[3]          # the wrist point in tool coordinates
    cdef double RMt[9]             # R_M^T
    cdef double x6[3]              # a direction normal to axis 6
    cdef double e1[3]
    cdef double e2[3]              # the plane normal to the parallel axes (complex coordinates)
    cdef double C2r, C2i
    cdef TwoLink chain23           # joints 2-3 as a planar two-link chain

    def __init__(self, Chain chain, ref0, z, c, w_tool, R_M, x6, e1, e2, a, b, C2, scale, limits, limit_tol):
        super().__init__(chain, limits, [True] * 6, scale, limit_tol, ref0, 8, 0)
        cdef int i
        for i in range(6):
            _copy3(z[i], self.z[i])
            _copy3(c[i], self.c[i])
        _copy3(w_tool, self.w_tool)
        _copy33(np.asarray(R_M).T, self.RMt)
        _copy3(x6, self.x6)
        _copy3(e1, self.e1)
        _copy3(e2, self.e2)
        self.chain23 = two_link(a, b)
        self.C2r, self.C2i = C2.real, C2.imag

    cdef bint _shoulder(self, const double* Rd, const double* pd, const double* u, double K0,
                        double q1_ref, double* q1, double* r, double* rho) noexcept nogil:
        """Joint 1 turns the wrist point p_w = R_d w_tool + p_d back into the plane u . x = K0 + u . c_1:
        A cos q1 + B sin q1 = K. Sets q1[2], r = p_w - c_1, rho = |(A, B)| / scale."""
        cdef double v[3]
        cdef int i
        mat3_vec(Rd, self.w_tool, v)
        for i in range(3):
            r[i] = v[i] + pd[i] - self.c[0][i]
        cdef double zr = dot3(r, self.z[0]), nz = dot3(u, self.z[0])
        cross3(u, self.z[0], v)
        cdef double A = dot3(r, u) - zr * nz, B = -dot3(r, v), K = K0 - zr * nz
        rho[0] = hypot(A, B) / self.scale
        return cos_sin_equation(A / self.scale, B / self.scale, K / self.scale, q1_ref, q1)

    cdef void _plane_offset(self, const double* x, double* d) noexcept nogil:
        """d (re, im) = x in the plane's complex coordinates, minus axis 2's point."""
        d[0] = dot3(x, self.e1) - self.C2r
        d[1] = dot3(x, self.e2) - self.C2i


cdef class SphericalWristKernel(_Kernel6R):
    """Axes 2 || 3 and axes 4-6 meeting at the wrist centre (see ``analytic6r.SphericalWrist6R``)."""

    cdef double K0, sigma3

    def __init__(self, Chain chain, ref0, z, c, w_tool, R_M, x6, e1, e2, a, b, C2, scale, limits, limit_tol,
                 k, sigma3):
        super().__init__(chain, ref0, z, c, w_tool, R_M, x6, e1, e2, a, b, C2, scale, limits, limit_tol)
        self.K0 = k - dot3(self.z[1], self.c[0])
        self.sigma3 = sigma3

    cdef signed char solve_one(self, const double* Rd, const double* pd, const double* ref, double* Q,
                               unsigned char* valid, double* detail, unsigned char* uncertain,
                               double* work) noexcept nogil:
        cdef unsigned char geometric[8]
        cdef double q1[2]
        cdef double x2[2]
        cdef double x3[2]
        cdef double q4[2]
        cdef double q5[2]
        cdef double r[3]
        cdef double y[3]
        cdef double d[2]
        cdef double t6[3]
        cdef double v[3]
        cdef double x6t[3]
        cdef double R[9]
        cdef double R12[9]
        cdef double R123[9]
        cdef double Rw[9]
        cdef double RdM[9]
        cdef double R4[9]
        cdef double R5[9]
        cdef double R45[9]
        cdef double rho, q6
        cdef int s1, s2, s3, i, b
        cdef bint ok1, ok23, ok45, any_ok1 = False, any_ok123 = False
        cdef double* z0 = self.z[0]
        detail[0] = INFINITY
        # 1. shoulder: joint 1 turns the wrist centre back into the plane of joints 2-3 (2 shoulders)
        ok1 = self._shoulder(Rd, pd, self.z[1], self.K0, ref[0], q1, r, &rho)
        mat3_mul(Rd, self.RMt, RdM)
        for s1 in range(2):
            # 2. elbow: joints 2, 3 as a planar chain to the turned-back wrist centre (2 elbows)
            rodrigues(z0, -q1[s1], R)
            mat3_vec(R, r, y)
            for i in range(3):
                y[i] += self.c[0][i]
            self._plane_offset(y, d)
            detail[0] = min(detail[0], hypot(d[0], d[1]))
            ok23 = planar_two_link(&self.chain23, d[0], d[1], ref[1], x2, x3)
            any_ok1 |= ok1
            any_ok123 |= ok1 and ok23
            rodrigues(z0, q1[s1], R)
            for s2 in range(2):
                # 3. wrist: Rot(z4, q4) Rot(z5, q5) carry z6 onto R_w z6 (2 wrists), q6 the rest
                rodrigues(self.z[1], x2[s2], R123)
                mat3_mul(R, R123, R12)
                rodrigues(self.z[2], self.sigma3 * x3[s2], Rw)
                mat3_mul(R12, Rw, R123)
                mat3T_mul(R123, RdM, Rw)                      # R_w = R123^T R_d R_M^T
                mat3_vec(Rw, self.z[5], t6)
                ok45 = two_axes(self.z[3], self.z[4], self.z[5], t6, ref[3], q4, q5)
                mat3_vec(Rw, self.x6, v)
                for s3 in range(2):
                    b = 4 * s1 + 2 * s2 + s3
                    rodrigues(self.z[3], q4[s3], R4)
                    rodrigues(self.z[4], q5[s3], R5)
                    mat3_mul(R4, R5, R45)
                    mat3T_vec(R45, v, x6t)
                    q6 = angle_about(self.z[5], self.x6, x6t, 0.0)
                    Q[6 * b] = q1[s1]
                    Q[6 * b + 1] = x2[s2]
                    Q[6 * b + 2] = self.sigma3 * x3[s2]
                    Q[6 * b + 3] = q4[s3]
                    Q[6 * b + 4] = q5[s3]
                    Q[6 * b + 5] = q6
                    geometric[b] = ok1 and ok23 and ok45
        i = wrap_branches(Q, geometric, valid, ref, self.lo, self.hi, self.rev, 8, 6, self.limit_tol)
        # wrist centre (nearly) on axis 1: q1 is free or ill-determined; not proven unreachable
        uncertain[0] = i != 0 and rho < _NEAR_SINGULAR
        return _outcome(i, uncertain[0], any_ok1, any_ok123)


cdef class ThreeParallelKernel(_Kernel6R):
    """Axes 2 || 3 || 4 and axes 5, 6 meeting (see ``analytic6r.ThreeParallel6R``)."""

    cdef double K0, A5, B5, zg_uz
    cdef double sigma[3]
    cdef double Minv_R[9]
    cdef double Minv_p[3]

    def __init__(self, Chain chain, ref0, z, c, w_tool, R_M, x6, e1, e2, a, b, C2, scale, limits, limit_tol,
                 w, sigma, M_inv):
        super().__init__(chain, ref0, z, c, w_tool, R_M, x6, e1, e2, a, b, C2, scale, limits, limit_tol)
        cdef double* u = self.z[1]
        cdef double* g = self.z[5]
        cdef double wc[3]
        cdef double v[3]
        _copy3(w, wc)
        self.K0 = dot3(u, wc) - dot3(u, self.c[0])
        cdef double zg = dot3(self.z[4], g), uz = dot3(u, self.z[4])
        self.A5 = dot3(u, g) - zg * uz
        cross3(self.z[4], g, v)
        self.B5 = dot3(u, v)
        self.zg_uz = zg * uz
        _copy3(sigma, self.sigma)
        _copy33(M_inv[:3, :3], self.Minv_R)
        _copy3(M_inv[:3, 3], self.Minv_p)

    cdef bint _rest(self, double phi, const double* R1, const double* R5, const double* W,
                    const double* Rd, const double* pd, double q2_ref, double* q6, double* psi2,
                    double* psi3, double* dist) noexcept nogil:
        """For a given phi (joints 2-4 about u): q6, both elbows (psi2, psi3) of joints 2-3 and whether
        they reach the point on axis 4; dist = its distance from axis 2."""
        cdef double* u = self.z[1]
        cdef double R[9]
        cdef double RW[9]
        cdef double R6[9]
        cdef double v[3]
        cdef double x[3]
        cdef double d[2]
        cdef int i
        rodrigues(u, -phi, R)
        mat3_mul(R, W, RW)
        mat3T_mul(R5, RW, R6)                                  # R6 = R5^T Rot(u, phi)^T W
        mat3_vec(R6, self.x6, v)
        q6[0] = angle_about(self.z[5], self.x6, v, 0.0)
        # the point on axis 4, moved by joints 2 and 3 only: Y = E1^-1 T_d M^-1 E6^-1 E5^-1 c4
        for i in range(3):
            v[i] = self.c[3][i] - self.c[4][i]
        mat3T_vec(R5, v, x)
        for i in range(3):
            x[i] += self.c[4][i] - self.c[5][i]
        rodrigues(self.z[5], -q6[0], R)
        mat3_vec(R, x, v)
        for i in range(3):
            v[i] += self.c[5][i]
        mat3_vec(self.Minv_R, v, x)
        for i in range(3):
            x[i] += self.Minv_p[i]
        mat3_vec(Rd, x, v)
        for i in range(3):
            v[i] += pd[i] - self.c[0][i]
        mat3T_vec(R1, v, x)
        for i in range(3):
            x[i] += self.c[0][i]
        self._plane_offset(x, d)
        dist[0] = hypot(d[0], d[1])
        return planar_two_link(&self.chain23, d[0], d[1], self.sigma[0] * q2_ref,
                               psi2, psi3)

    cdef signed char solve_one(self, const double* Rd, const double* pd, const double* ref, double* Q,
                               unsigned char* valid, double* detail, unsigned char* uncertain,
                               double* work) noexcept nogil:
        cdef unsigned char geometric[8]
        cdef double* u = self.z[1]
        cdef double* g = self.z[5]
        cdef double q1[2]
        cdef double q5[2]
        cdef double psi2[2]
        cdef double psi3[2]
        cdef double c2[2]
        cdef double c3[2]
        cdef double r[3]
        cdef double z6t[3]
        cdef double a5[3]
        cdef double Wg[3]
        cdef double v[3]
        cdef double Rt[9]
        cdef double R1[9]
        cdef double W[9]
        cdef double R5[9]
        cdef double rho, phi, q6, dist, cand, c6, cdist, phi_ref, rho_a5
        cdef int s1, s2, s3, i, b, k
        cdef bint ok1, ok5, ok23, free, any_ok1 = False, any_ok15 = False, any_free = False
        detail[0] = INFINITY
        # 1. shoulder: joint 1 turns the point where axes 5, 6 meet into the plane of joints 2-4
        ok1 = self._shoulder(Rd, pd, u, self.K0, ref[0], q1, r, &rho)
        mat3_mul(Rd, self.RMt, Rt)                              # R(q) at the target, without the tool
        mat3_vec(Rt, g, z6t)
        phi_ref = self.sigma[0] * ref[1] + self.sigma[1] * ref[2] + self.sigma[2] * ref[3]
        for s1 in range(2):
            rodrigues(self.z[0], q1[s1], R1)
            # 2. wrist: u . Rot(z5, q5) g = u . (R1^T z6_target) (2 wrists)
            mat3_vec(R1, u, v)
            ok5 = cos_sin_equation(self.A5, self.B5, dot3(z6t, v) - self.zg_uz, ref[4], q5)
            any_ok1 |= ok1
            any_ok15 |= ok1 and ok5
            mat3T_mul(R1, Rt, W)                               # W = R1^T R_d R_M^T = Rot(u, phi) R5 R6
            mat3_vec(W, g, Wg)
            for s2 in range(2):
                # 3. phi (joints 2-4 about u) and q6; 4. joints 2-3 reach the point on axis 4 (2 elbows)
                rodrigues(self.z[4], q5[s2], R5)
                mat3_vec(R5, g, a5)
                phi = angle_about(u, a5, Wg, phi_ref)
                ok23 = self._rest(phi, R1, R5, W, Rd, pd, ref[1], &q6, psi2, psi3, &dist)
                # Wrist singularity (axis 6 along u): phi and q6 trade off, but the point on axis 4 -
                # and with it the reach of joints 2-3 - depends on the split. Take the preferred phi if
                # it reaches, else the reaching phi nearest to it on a 1-degree grid.
                rho_a5 = dot3(a5, u)
                for i in range(3):
                    v[i] = a5[i] - rho_a5 * u[i]
                free = dot3(v, v) < _NEAR_SINGULAR * _NEAR_SINGULAR
                any_free |= free
                if free and not ok23:
                    for k in range(2 * GRID_STEPS + 1):       # 0, +1, -1, +2, ... degrees
                        cand = phi_ref + DEG * ((k + 1) // 2) * (1 if k % 2 else -1)
                        if self._rest(cand, R1, R5, W, Rd, pd, ref[1], &c6, c2, c3, &cdist):
                            phi, q6, dist, ok23 = cand, c6, cdist, True
                            psi2[0], psi2[1], psi3[0], psi3[1] = c2[0], c2[1], c3[0], c3[1]
                            break
                detail[0] = min(detail[0], dist)
                for s3 in range(2):
                    b = 4 * s1 + 2 * s2 + s3
                    Q[6 * b] = q1[s1]
                    Q[6 * b + 1] = self.sigma[0] * psi2[s3]
                    Q[6 * b + 2] = self.sigma[1] * psi3[s3]
                    Q[6 * b + 3] = self.sigma[2] * (phi - psi2[s3] - psi3[s3])
                    Q[6 * b + 4] = q5[s2]
                    Q[6 * b + 5] = q6
                    geometric[b] = ok1 and ok5 and ok23
        i = wrap_branches(Q, geometric, valid, ref, self.lo, self.hi, self.rev, 8, 6, self.limit_tol)
        # free joints set to preferred values (wrist point on axis 1; axis 6 along u): not proven
        uncertain[0] = i != 0 and (rho < _NEAR_SINGULAR or any_free)
        return _outcome(i, uncertain[0], any_ok1, any_ok15)
