"""Compiled closed-form IK of SCARA-type arms (the kernel behind ``kinematics.scara``).

Every joint axis is parallel to one direction u; 2 or 3 revolute joints and any number of prismatic
ones. Per target: the orientation must be a turn about u, the travel along u is split among the
prismatic joints (``split_travel``), the first two revolute joints are a planar two-link chain, and a
third (the wrist) takes the remaining turn. Both elbows are returned, wrapped into the limits
(``solve_one``; the batch loop and the single-target entry are the base class's,
``closed_form_kernel.ClosedFormKernel``).

Outcome codes per target (``code``), the first step that fails when no branch is valid:
0 a valid branch exists; 1 the orientation is not a turn about u (``detail``: the tilt, radians);
2 the travel along u is out of the prismatic joints' reach (``detail``: the travel); 3 the point is
out of planar reach (``detail``: its distance from the first axis); 4 the orientation does not match
the position (no wrist joint); 5 geometric solutions exist but violate the joint limits.
"""

import numpy as np

cimport numpy as cnp
from libc.math cimport atan2, cos, fabs, hypot, sin, sqrt
from robkin.compiled.ik.closed_form_kernel cimport ClosedFormKernel
from robkin.compiled.chain.fk cimport Chain
from robkin.compiled.runtime.linalg cimport dot3, mat3_mul, mat3_vec
from robkin.compiled.ik.subproblems cimport COS_SLACK, planar_two_link, TwoLink, two_link, wrap_branches

cnp.import_array()

#: Target orientation must be a rotation about u to this (|R u - u|, radians); a looser target has
#: no exact solution. 1e-9: rounding of targets computed by FK is ~1e-15, and the IK verifies to 1e-9.
ORIENTATION_SLACK = 1e-9
cdef double _ORIENTATION_SLACK = ORIENTATION_SLACK


cdef void _split_travel(double h, const double* s, const double* ref, const double* lo, const double* hi,
                        Py_ssize_t m, double* q, unsigned char* free) noexcept nogil:
    """q (m) nearest to ref with s . q = h and lo <= q <= hi; ``free`` is scratch (m).

    The projection is q = clip(ref + lam s, lo, hi) for one scalar lam. Joints that hit a limit stay
    there as lam moves on (the sum is monotone in lam), so fixing them and re-spreading the remainder
    over the others converges in at most m rounds.
    """
    cdef Py_ssize_t j, it
    cdef double nfree, lam
    cdef bint over
    for j in range(m):
        q[j] = ref[j]
        free[j] = 1
    for it in range(m):
        nfree = 0.0
        lam = h
        for j in range(m):
            if free[j]:
                nfree += s[j] * s[j]
                lam -= s[j] * ref[j]
            else:
                lam -= s[j] * q[j]
        lam /= max(nfree, 1e-300)                 # all joints fixed: nothing left to spread
        over = False
        for j in range(m):
            if free[j]:
                q[j] = ref[j] + lam * s[j]
                if q[j] < lo[j] or q[j] > hi[j]:
                    q[j] = min(max(q[j], lo[j]), hi[j])
                    free[j] = 0
                    over = True
        if not over:
            break


def split_travel(h, s, ref, lo, hi):
    """The q (N, m) nearest to ref (N, m) with s . q = h (N,) and lo <= q <= hi (m,); s: (m,) or (N, m)."""
    ref_arr = np.ascontiguousarray(ref, dtype=np.float64)
    cdef Py_ssize_t N = ref_arr.shape[0], m = ref_arr.shape[1], n
    cdef const double[::1] h_v = np.ascontiguousarray(h, dtype=np.float64)
    cdef const double[:, ::1] s_v = np.ascontiguousarray(np.broadcast_to(s, (N, m)), dtype=np.float64)
    cdef const double[:, ::1] r_v = ref_arr
    cdef const double[::1] lo_v = np.ascontiguousarray(lo, dtype=np.float64)
    cdef const double[::1] hi_v = np.ascontiguousarray(hi, dtype=np.float64)
    if h_v.shape[0] != N or lo_v.shape[0] != m or hi_v.shape[0] != m:
        raise ValueError(f"split_travel: expected h ({N},), lo and hi ({m},) for ref {ref_arr.shape}")
    out = np.empty((N, m))
    cdef double[:, ::1] q = out
    cdef unsigned char[::1] free = np.empty(m, np.uint8)
    if m:
        for n in range(N):
            _split_travel(h_v[n], &s_v[n, 0], &r_v[n, 0], &lo_v[0], &hi_v[0], m, &q[n, 0], &free[0])
    return out


cdef class ScaraKernel(ClosedFormKernel):
    """Built once per robot by ``kinematics.scara.ScaraSolver`` from the geometry it detected."""

    cdef double u[3]
    cdef double e1[3]
    cdef double e2[3]
    cdef double RMt[9]
    cdef double pM[3]
    cdef double pit[3]                         # the wrist point (or tool origin) in tool coordinates
    cdef double C1r, C1i
    cdef TwoLink planar                        # the first two revolute joints, planar
    cdef Py_ssize_t nr, m
    cdef Py_ssize_t[::1] ridx, pidx
    cdef double[::1] sigma, s, p_lo, p_hi      # p_: limits of the prismatic joints

    def __init__(self, Chain chain, ref0, u, e1, e2, R_M, p_M, point_in_tool, a, b, C1, scale, ridx, pidx,
                 sigma, s, limits, revolute, limit_tol):
        # scratch of solve_one: the prismatic joints' preferences, their values and flags (m each)
        super().__init__(chain, limits, revolute, scale, limit_tol, ref0, 2, 3 * max(len(pidx), 1))
        cdef int i, j
        for i in range(3):
            self.u[i], self.e1[i], self.e2[i] = u[i], e1[i], e2[i]
            self.pM[i], self.pit[i] = p_M[i], point_in_tool[i]
            for j in range(3):
                self.RMt[3 * i + j] = R_M[j][i]
        self.planar = two_link(a, b)
        self.C1r, self.C1i = C1.real, C1.imag
        self.ridx, self.pidx = np.array(ridx, np.intp), np.array(pidx, np.intp)
        self.nr, self.m = len(ridx), len(pidx)
        self.sigma, self.s = np.array(sigma, float), np.array(s, float)
        lim = np.asarray(limits, float)
        self.p_lo, self.p_hi = lim[pidx, 0].copy(), lim[pidx, 1].copy()

    cdef signed char solve_one(self, const double* Rd, const double* pd, const double* ref, double* Q,
                               unsigned char* valid, double* detail, unsigned char* uncertain,
                               double* work) noexcept nogil:
        cdef Py_ssize_t m1 = max(self.m, 1)
        cdef double* pref = work
        cdef double* qp = work + m1
        cdef unsigned char* scratch = <unsigned char*>(work + 2 * m1)
        cdef double rel[9]
        cdef double v[3]
        cdef double point[3]
        cdef double x1[2]
        cdef double x2[2]
        cdef double ang[3]
        cdef unsigned char geometric[2]
        cdef double tilt, phi, h, miss, dr, di, sh
        cdef bint orient_ok, vert_ok, reach_ok
        cdef bint wrist_ok[2]
        cdef Py_ssize_t j, e, n = self.n
        # orientation: Rot(u, phi) R_M
        mat3_mul(Rd, self.RMt, rel)
        mat3_vec(rel, self.u, v)
        tilt = sqrt((v[0] - self.u[0]) ** 2 + (v[1] - self.u[1]) ** 2 + (v[2] - self.u[2]) ** 2)
        orient_ok = tilt <= _ORIENTATION_SLACK
        mat3_vec(rel, self.e1, v)
        phi = atan2(dot3(v, self.e2), dot3(v, self.e1))
        # vertical travel, split among the prismatic joints; the split meets h exactly unless the
        # limits cut it short, and a shortfall within rounding of the robot's size (COS_SLACK
        # relative) is still a solution (FK checks it afterwards)
        h = ((pd[0] - self.pM[0]) * self.u[0] + (pd[1] - self.pM[1]) * self.u[1]
             + (pd[2] - self.pM[2]) * self.u[2])
        sh = 0.0
        for j in range(self.m):
            pref[j] = ref[self.pidx[j]]
        if self.m:
            _split_travel(h, &self.s[0], pref, &self.p_lo[0], &self.p_hi[0], self.m, qp, scratch)
        for j in range(self.m):
            sh += qp[j] * self.s[j]
        vert_ok = fabs(sh - h) <= COS_SLACK * self.scale
        # planar chain: the first two revolute joints bring the wrist point (or tool origin) there
        mat3_vec(Rd, self.pit, point)
        for j in range(3):
            point[j] += pd[j]
        dr = dot3(point, self.e1) - self.C1r
        di = dot3(point, self.e2) - self.C1i
        reach_ok = planar_two_link(&self.planar, dr, di,
                                   self.sigma[0] * ref[self.ridx[0]], x1, x2)
        for e in range(2):
            ang[0], ang[1] = x1[e], x2[e]
            if self.nr == 3:
                ang[2] = phi - x1[e] - x2[e]
                wrist_ok[e] = True
            else:
                miss = phi - x1[e] - x2[e]
                miss = atan2(sin(miss), cos(miss))
                wrist_ok[e] = fabs(miss) <= _ORIENTATION_SLACK
                if not wrist_ok[e] and fabs(miss) * self.planar.lb <= COS_SLACK * self.scale:
                    # a tool origin close to the second axis (|b| ~1e-7 of the robot, seen) fixes that
                    # joint's angle only to rounding / |b|, beyond the slack above, while the target's
                    # orientation fixes it exactly: the orientation's angle, which moves the tool
                    # origin by |b| |miss| <= rounding of the robot's size (FK checks it afterwards)
                    ang[1] = x2[e] + miss
                    wrist_ok[e] = True
            for j in range(self.nr):
                Q[e * n + self.ridx[j]] = ang[j] * self.sigma[j]
            for j in range(self.m):
                Q[e * n + self.pidx[j]] = qp[j]
            geometric[e] = reach_ok and wrist_ok[e] and orient_ok and vert_ok
        uncertain[0] = False
        j = wrap_branches(Q, geometric, valid, ref, self.lo, self.hi, self.rev, 2, n, self.limit_tol)
        if j == 0:
            return 0
        if not orient_ok:
            detail[0] = tilt
            return 1
        if not vert_ok:
            detail[0] = h
            return 2
        if not reach_ok:
            detail[0] = hypot(dr, di)
            return 3
        return 4 if j == 1 else 5
