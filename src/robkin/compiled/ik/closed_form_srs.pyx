"""Compiled closed-form IK of SRS arms (7R, spherical shoulder and wrist) at a given arm angle.

The kernel behind ``kinematics.srs``; the geometry (shoulder point S, wrist centre W_0, elbow point E_0,
the elbow equation's constants) comes from ``kinematics.srs_geometry``. Per target (R_d, p_d) and arm
angle psi:

1. the wrist centre W = R_d w_tool + p_d; joint 4 solves A cos q4 + B sin q4 = C0 - |W - S|^2 / 2
   (``cos_sin_equation``'s form, two roots: the elbow branches);
2. per root, the shoulder rotation R_123 carries the home frame (S -> W_0 turned by q4, the elbow's part
   across it) onto the target frame (S -> W, the elbow direction psi prescribes): R_123 = F_t F_s^T; it is
   split into turns about axes 1, 2, 3 (``two_axes`` for the first two, two branches; ``angle_about`` for
   the third);
3. the wrist rotation (R_123 Rot(a4, q4))^T R_d R_home^T split likewise about axes 5, 6, 7.

Branch j = 4 e + 2 s + w (e: elbow root +acos / -acos; s, w: the +gamma / -gamma pair of ``two_axes``);
``kinematics.srs.BRANCHES`` names them. Outcome codes: 0 some branch exists; 1 out of reach; 2 the elbow
on the shoulder-wrist line (psi undefined); 3 no shoulder or wrist rotation fits.
"""

import numpy as np

cimport numpy as cnp
from libc.math cimport acos, atan2, cos, fabs, sin, sqrt
from robkin.compiled.ik.closed_form_kernel cimport ClosedFormKernel
from robkin.compiled.chain.fk cimport Chain
from robkin.compiled.runtime.linalg cimport cross3, dot3, mat3_mul, mat3_vec, norm3, rodrigues
from robkin.compiled.ik.subproblems cimport angle_about, c_doubles, mat3T_mul, new_array, read_pose, two_axes, \
    wrap_into_limits

cnp.import_array()

cdef enum:
    NB = 8          # branches: 2 elbows x 2 shoulders x 2 wrists

#: |cos q4| may exceed 1 by rounding at full stretch: 1e-12 relative is ~1e4 ulps
cdef double REACH_TOL = 1e-12
#: the elbow's distance from the shoulder-wrist line below this (relative to |E_0 - S|) is rounding of a
#: stretched or folded elbow, and the reference direction's part across S -> W below this is rounding
#: of S -> W along joint 1's axis
cdef double FLAT_TOL = 1e-9


cdef class SRSKernel(ClosedFormKernel):
    """One SRS arm's geometry (base frame, q = 0; see the module docstring)."""

    cdef double a[7][3]
    cdef double S[3]
    cdef double W0p4[3]            # W_0 - p_4
    cdef double p4S[3]             # p_4 - S
    cdef double u0[3]              # E_0 - S
    cdef double u0n
    cdef double w_tool[3]
    cdef double RHt[9]             # the tool rotation at q = 0, transposed
    cdef double zref[3]
    cdef double zalt[3]
    cdef double y3[3]              # a direction across axis 3, and across axis 7
    cdef double y7[3]
    cdef double A, B, C0

    def __init__(self, Chain chain, limits, ref0, double scale, double limit_tol, axes, S, W0, p4, E0, w_tool,
                 R_home, zref, zalt, double A, double B, double C0):
        super().__init__(chain, limits, [True] * 7, scale, limit_tol, ref0, NB, 1)
        cdef int i, j
        ax = np.asarray(axes, dtype=np.float64)
        for i in range(7):
            for j in range(3):
                self.a[i][j] = ax[i, j]
        RH = np.asarray(R_home, dtype=np.float64)
        for i in range(3):
            self.S[i] = S[i]
            self.W0p4[i] = W0[i] - p4[i]
            self.p4S[i] = p4[i] - S[i]
            self.u0[i] = E0[i] - S[i]
            self.w_tool[i] = w_tool[i]
            self.zref[i] = zref[i]
            self.zalt[i] = zalt[i]
            for j in range(3):
                self.RHt[3 * i + j] = RH[j, i]
        self.u0n = norm3(self.u0)
        for k, out in ((2, 0), (6, 1)):
            w = ax[k]
            y = np.cross(w, [1.0, 0.0, 0.0] if abs(w[0]) < 0.9 else [0.0, 1.0, 0.0])
            y /= np.linalg.norm(y)
            for i in range(3):
                if out == 0:
                    self.y3[i] = y[i]
                else:
                    self.y7[i] = y[i]
        self.A, self.B, self.C0 = A, B, C0

    cdef bint _three(self, int k, const double* R, double* q, bint* ok) noexcept nogil:
        """Both splits q (2 x 3) of R = Rot(a_k, .) Rot(a_k+1, .) Rot(a_k+2, .) (k = 0 or 4); ok: they exist."""
        cdef double x[3]
        cdef double x1[2]
        cdef double x2[2]
        cdef double R1[9]
        cdef double R2[9]
        cdef double R12[9]
        cdef double Rt[9]
        cdef double Ry[3]
        cdef double z[3]
        cdef const double* y = &self.y7[0]
        cdef int s
        if k == 0:
            y = &self.y3[0]
        mat3_vec(R, self.a[k + 2], x)
        ok[0] = two_axes(self.a[k], self.a[k + 1], self.a[k + 2], x, 0.0, x1, x2)
        mat3_vec(R, y, Ry)
        for s in range(2):
            rodrigues(self.a[k], x1[s], R1)
            rodrigues(self.a[k + 1], x2[s], R2)
            mat3_mul(R1, R2, R12)
            # z = R12^T R y
            z[0] = R12[0] * Ry[0] + R12[3] * Ry[1] + R12[6] * Ry[2]
            z[1] = R12[1] * Ry[0] + R12[4] * Ry[1] + R12[7] * Ry[2]
            z[2] = R12[2] * Ry[0] + R12[5] * Ry[1] + R12[8] * Ry[2]
            q[3 * s] = x1[s]
            q[3 * s + 1] = x2[s]
            q[3 * s + 2] = angle_about(self.a[k + 2], y, z, 0.0)
        return ok[0]

    cdef signed char solve_psi(self, const double* Rd, const double* pd, double psi, double* Q,
                               unsigned char* exists) noexcept nogil:
        """Every candidate Q (8, 7) (raw angles) of one target at arm angle psi; exists (8,); the code."""
        cdef double W[3]
        cdef double w[3]
        cdef double wh[3]
        cdef double n1[3]
        cdef double n2[3]
        cdef double nt[3]
        cdef double t3[3]
        cdef double v0[3]
        cdef double n0[3]
        cdef double s3[3]
        cdef double R4[9]
        cdef double R123[9]
        cdef double Rr[9]
        cdef double Rrr[9]
        cdef double R1234[9]
        cdef double Rw[9]
        cdef double Rt[9]
        cdef double sh[6]
        cdef double wr[6]
        cdef bint ok_s, ok_w, flat = False
        cdef int i, j, e, s, k, b
        cdef double d, m, c, proj, q4
        for j in range(NB):
            exists[j] = 0
            for i in range(7):
                Q[7 * j + i] = 0.0
        mat3_vec(Rd, self.w_tool, W)
        for i in range(3):
            w[i] = W[i] + pd[i] - self.S[i]
        d = norm3(w)
        cdef double r = sqrt(self.A * self.A + self.B * self.B)
        cdef double ratio = (self.C0 - 0.5 * d * d) / r
        if fabs(ratio) > 1.0 + REACH_TOL or d == 0.0:
            return 1
        cdef double phi = atan2(self.B, self.A)
        cdef double ac = acos(1.0 if ratio > 1.0 else (-1.0 if ratio < -1.0 else ratio))
        for i in range(3):
            wh[i] = w[i] / d
        proj = dot3(wh, self.zref)
        for i in range(3):
            n1[i] = self.zref[i] - proj * wh[i]
        m = norm3(n1)
        if m <= FLAT_TOL:
            proj = dot3(wh, self.zalt)
            for i in range(3):
                n1[i] = self.zalt[i] - proj * wh[i]
            m = norm3(n1)
        for i in range(3):
            n1[i] /= m
        cross3(wh, n1, n2)
        c, m = cos(psi), sin(psi)
        for i in range(3):
            nt[i] = c * n1[i] + m * n2[i]
        cross3(wh, nt, t3)
        mat3_mul(Rd, self.RHt, Rt)
        for e in range(2):
            q4 = phi + (ac if e == 0 else -ac)
            rodrigues(self.a[3], q4, R4)
            mat3_vec(R4, self.W0p4, v0)
            for i in range(3):
                v0[i] += self.p4S[i]
            m = norm3(v0)
            for i in range(3):
                v0[i] /= m
            proj = dot3(v0, self.u0)
            for i in range(3):
                n0[i] = self.u0[i] - proj * v0[i]
            m = norm3(n0)
            if m <= FLAT_TOL * self.u0n:
                flat = True
                continue
            for i in range(3):
                n0[i] /= m
            cross3(v0, n0, s3)
            # R123 = F_t F_s^T, columns of F_t: wh, nt, t3; of F_s: v0, n0, s3
            for i in range(3):
                for j in range(3):
                    R123[3 * i + j] = wh[i] * v0[j] + nt[i] * n0[j] + t3[i] * s3[j]
            self._three(0, R123, sh, &ok_s)
            for s in range(2):
                rodrigues(self.a[0], sh[3 * s], Rr)
                rodrigues(self.a[1], sh[3 * s + 1], R1234)
                mat3_mul(Rr, R1234, Rrr)
                rodrigues(self.a[2], sh[3 * s + 2], Rr)
                mat3_mul(Rrr, Rr, R1234)
                mat3_mul(R1234, R4, Rrr)                 # R1 R2 R3 R4
                mat3T_mul(Rrr, Rt, Rw)
                self._three(4, Rw, wr, &ok_w)
                for k in range(2):
                    b = 4 * e + 2 * s + k
                    for i in range(3):
                        Q[7 * b + i] = sh[3 * s + i]
                        Q[7 * b + 4 + i] = wr[3 * k + i]
                    Q[7 * b + 3] = q4
                    exists[b] = ok_s and ok_w
        for j in range(NB):
            if exists[j]:
                return 0
        return 2 if flat else 3

    def candidates(self, targets, psi, q_ref=None):
        """Every candidate of targets (N, 4, 4) at arm angles psi (N,).

        Returns Q (N, 8, 7) (raw angles; with q_ref (N, 7) wrapped into the limits nearest q_ref),
        exists (N, 8) bool, valid (N, 8) bool (exists and within the limits; None without q_ref) and
        code (N,) int8 (see the module docstring).
        """
        cdef cnp.ndarray T = c_doubles(targets, 3, 4, "targets")
        cdef Py_ssize_t N = cnp.PyArray_DIM(T, 0), k, j
        cdef cnp.ndarray P = c_doubles(psi, 1, N, "psi")
        cdef cnp.ndarray R
        cdef const double* ref = NULL
        if q_ref is not None:
            R = c_doubles(q_ref, 2, 7, "q_ref")
            if cnp.PyArray_DIM(R, 0) != N:
                raise ValueError(f"q_ref: expected {N} rows")
            ref = <const double*>cnp.PyArray_DATA(R)
        cdef cnp.ndarray Q = new_array(3, N, NB, 7, cnp.NPY_DOUBLE)
        cdef cnp.ndarray ex = new_array(2, N, NB, 0, cnp.NPY_BOOL)
        cdef cnp.ndarray valid = new_array(2, N, NB, 0, cnp.NPY_BOOL)
        cdef cnp.ndarray code = new_array(1, N, 0, 0, cnp.NPY_INT8)
        cdef const double* t = <const double*>cnp.PyArray_DATA(T)
        cdef const double* p = <const double*>cnp.PyArray_DATA(P)
        cdef double* q = <double*>cnp.PyArray_DATA(Q)
        cdef unsigned char* e = <unsigned char*>cnp.PyArray_DATA(ex)
        cdef unsigned char* v = <unsigned char*>cnp.PyArray_DATA(valid)
        cdef signed char* c = <signed char*>cnp.PyArray_DATA(code)
        cdef double Rd[9]
        cdef double pd[3]
        with nogil:
            for k in range(N):
                read_pose(t + 16 * k, Rd, pd)
                c[k] = self.solve_psi(Rd, pd, p[k], q + NB * 7 * k, e + NB * k)
                if ref != NULL:
                    for j in range(NB):
                        v[NB * k + j] = wrap_into_limits(q + 7 * (NB * k + j), ref + 7 * k, self.lo, self.hi,
                                                         self.rev, 7, self.limit_tol) and e[NB * k + j]
        return Q, ex, (valid if ref != NULL else None), code
