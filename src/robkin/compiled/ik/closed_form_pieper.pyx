"""Compiled closed-form IK of 6R arms with a spherical wrist and any first three joints (Pieper's case).

The kernel behind ``kinematics.pieper.Pieper6R``: axes 4, 5, 6 meet at the wrist centre W, joints 1-3
are arbitrary (a 7-joint arm such as the KUKA iiwa or the Kinova Gen3 with one joint locked; reversed
chains cover arms whose first three axes meet). The general elimination (``closed_form_general6r``)
degenerates on these arms; they decouple instead:

1. The wrist centre is fixed by joints 4-6, so the target puts it at p_w = T_d M^-1 W_0.
2. With the chain T(q) = L_1 Z(q_1) L_2 Z(q_2) L_3 Z(q_3) ... (``fk.pxd``), Z(-q_1) L_1^-1 p_w =
   f(q_2, q_3) = L_2 Z(q_2) L_3 Z(q_3) w_3. Rotation about z keeps the z component and the length:
   two equations in (q_2, q_3), each linear in (1, cos, sin) of both (read off exactly by trigonometric
   interpolation at 3 x 3 angles). With x = tan(theta / 2) (angles from fixed random offsets) they are
   quadratics in x_2 whose coefficients are quadratic in x_3; their Sylvester resultant (4 x 4, quadratic
   in x_3) vanishes at the up to 4 real x_3: the eigenvalues of its 8 x 8 companion matrix
   (``elimination.quadratic_pencil_eigenvalues``: the compiled QR of ``hessenberg_qr.h``, or LAPACK
   ``dggev`` on the pencil when the leading coefficient is singular).
3. Per root: q_2 from the equation that depends on it more (2 candidates, checked against the other),
   q_1 from the turn that carries f onto L_1^-1 p_w (free where p_w is on axis 1: the preference), and
   the wrist R_w = Rot(z_4, q_4) Rot(z_5, q_5) Rot(z_6, q_6) by Paden-Kahan subproblem 2 and an angle
   (2 wrists). Every candidate is polished by Newton steps on the exact forward kinematics.

Outcome codes as ``closed_form_general6r``: 0 valid; 1 uncertain (roots existed, no branch converged);
2 no real root (out of reach); 3 only the joint limits reject the branches.
"""

import numpy as np

cimport numpy as cnp
from libc.math cimport atan, atan2, cos, fabs, hypot, sin, sqrt, INFINITY
from robkin.compiled.ik.closed_form_kernel cimport ClosedFormKernel
from robkin.compiled.chain.fk cimport Chain
from robkin.compiled.runtime.linalg cimport mat3_mul, mat3_vec, mat3T_vec, rodrigues, tf_inv, tf_mul
from robkin.compiled.ik.newton cimport CANDIDATE_TOL, newton_polish
from robkin.compiled.ik.subproblems cimport angle_about, cos_sin_equation, mat3T_mul, two_axes, wrap_branches
from robkin.compiled.ik.elimination cimport quadratic_pencil_eigenvalues

cnp.import_array()

cdef enum:
    NB = 32         # branches per target: 8 eigenvalues x 2 candidates of q2 x 2 wrists
    LWORK = 512

#: as in ``closed_form_general6r``: near-real eigenvalues are kept for the Newton polish to decide
cdef double IMAG_TOL = 1e-4
#: the leading coefficient S2 counts as singular below this pivot ratio (the companion matrix would
#: lose more than half the digits): the pencil then goes to LAPACK ``dggev``, as in the general 6R
cdef double S2_RCOND = 1e-8
#: a q2 candidate of the stronger equation is kept when the other equation's residual (squared robot
#: sizes) is below this: loose, since a double root leaves ~sqrt(eps) errors that Newton removes
cdef double OTHER_TOL = 1e-3
cdef double TWO_PI_3 = 2.0943951023931957


cdef class PieperKernel(ClosedFormKernel):
    """A 6R arm with axes 4-6 meeting (see the module docstring)."""

    cdef double Ls[3][16]          # L_1 .. L_3, lengths over the robot size
    cdef double L1inv[16]
    cdef double w3[3]              # the wrist centre in frame 3 (after joint 3's motion), scaled
    cdef double w_tool[3]          # the wrist centre in tool coordinates (length units)
    cdef double R0t[9]             # rotation of L_1 L_2 L_3, transposed: R123 = R(q) R0^T
    cdef double RMt[9]             # the tool rotation at q = 0, transposed
    cdef double z[3][3]            # axes 4-6 at q = 0 (base frame)
    cdef double x6[3]              # a direction normal to axis 6
    cdef double delta[2]           # the half-angle offsets of joints 2 and 3
    cdef double Vinv[9]
    cdef double W[9]

    def __init__(self, Chain chain, limits, ref0, double scale, double limit_tol, L, w0, R_M, z, x6, delta):
        super().__init__(chain, limits, [True] * 6, scale, limit_tol, ref0, NB, 512)
        cdef int i, j, k
        La = np.array(L, dtype=np.float64)
        for i in range(3):
            for j in range(4):
                for k in range(4):
                    self.Ls[i][4 * j + k] = La[i, j, k] / (scale if (k == 3 and j < 3) else 1.0)
        tf_inv(self.Ls[0], self.L1inv)
        L123 = La[0] @ La[1] @ La[2]
        w0 = np.asarray(w0, dtype=np.float64)
        w3 = np.linalg.solve(L123, np.append(w0, 1.0))[:3] / scale
        M = np.asarray(chain_tool(La), dtype=np.float64)
        wt = np.linalg.solve(M, np.append(w0, 1.0))[:3]
        for i in range(3):
            self.w3[i] = w3[i]
            self.w_tool[i] = wt[i]
            self.x6[i] = x6[i]
            for j in range(3):
                self.R0t[3 * i + j] = L123[j, i]
                self.RMt[3 * i + j] = R_M[j][i]
                self.z[i][j] = z[i][j]
        self.delta[0], self.delta[1] = delta[0], delta[1]
        samples = TWO_PI_3 * np.arange(3)
        V = np.column_stack([np.ones(3), np.cos(samples), np.sin(samples)])
        Vi = np.linalg.inv(V)
        H = np.array([[1.0, 1.0, 0.0], [0.0, 0.0, 2.0], [1.0, -1.0, 0.0]])
        Wm = H @ Vi
        for i in range(3):
            for j in range(3):
                self.W[3 * i + j] = Wm[i, j]
                self.Vinv[3 * i + j] = Vi[i, j]

    cdef void _f(self, double t2, double t3, double* f) noexcept nogil:
        """f = L_2 Z(t2) L_3 Z(t3) w_3 (scaled)."""
        cdef double c = cos(t3), s = sin(t3)
        cdef double g[3]
        cdef double h[3]
        cdef int i
        cdef const double* A = self.Ls[2]
        g[0] = c * self.w3[0] - s * self.w3[1]
        g[1] = s * self.w3[0] + c * self.w3[1]
        g[2] = self.w3[2]
        for i in range(3):
            h[i] = A[4 * i] * g[0] + A[4 * i + 1] * g[1] + A[4 * i + 2] * g[2] + A[4 * i + 3]
        c = cos(t2)
        s = sin(t2)
        g[0] = c * h[0] - s * h[1]
        g[1] = s * h[0] + c * h[1]
        g[2] = h[2]
        A = self.Ls[1]
        for i in range(3):
            f[i] = A[4 * i] * g[0] + A[4 * i + 1] * g[1] + A[4 * i + 2] * g[2] + A[4 * i + 3]

    cdef signed char solve_one(self, const double* Rd, const double* pd, const double* ref, double* Q,
                               unsigned char* valid, double* detail, unsigned char* uncertain,
                               double* work) noexcept nogil:
        cdef double pw[3]
        cdef double pp[3]
        cdef double f[3]
        cdef double e[2][9]            # the two equations at the 3 x 3 samples
        cdef double tc[2][9]           # their (1, cos, sin)^2 coefficients (index 3 i2 + i3)
        cdef double xc[2][9]           # their x-power coefficients (index 3 p2 + p3)
        cdef double A[64]
        cdef double B[64]
        cdef double Sq[48]
        cdef double col[4]
        cdef int piv[4]
        cdef double ar[8]
        cdef double ai[8]
        cdef double be[8]
        cdef double lw[LWORK]
        cdef double coef[2][3]         # per equation, alpha + beta cos t2' + gamma sin t2'
        cdef double t2c[2]
        cdef double q4[2]
        cdef double q5[2]
        cdef double qc[6]
        cdef double nw[6]
        cdef double T[16]
        cdef double X[16]
        cdef double R[9]
        cdef double R123[9]
        cdef double RdM[9]
        cdef double Rw[9]
        cdef double R4[9]
        cdef double R5[9]
        cdef double R45[9]
        cdef double t6[3]
        cdef double v[3]
        cdef double x6t[3]
        cdef unsigned char geometric[NB]
        cdef int i, j, k, m, r, s, w, strong, info, nb = 0
        cdef double pp2, x, t2, t3, c3, s3, res, other, q1
        cdef bint any_real = False
        detail[0] = INFINITY
        uncertain[0] = False
        for s in range(NB):
            geometric[s] = False
            for j in range(6):
                Q[6 * s + j] = 0.0
        # 1. the wrist centre, in joint 1's frame (scaled)
        mat3_vec(Rd, self.w_tool, v)
        for i in range(3):
            pw[i] = (v[i] + pd[i]) / self.scale
        for i in range(3):
            pp[i] = (self.L1inv[4 * i] * pw[0] + self.L1inv[4 * i + 1] * pw[1] + self.L1inv[4 * i + 2] * pw[2]
                     + self.L1inv[4 * i + 3])
        pp2 = pp[0] * pp[0] + pp[1] * pp[1] + pp[2] * pp[2]
        # 2. both equations at the samples, their coefficients, the Sylvester pencil in x3
        for i in range(3):
            for j in range(3):
                self._f(TWO_PI_3 * i + self.delta[0], TWO_PI_3 * j + self.delta[1], f)
                e[0][3 * i + j] = f[2] - pp[2]
                e[1][3 * i + j] = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - pp2
        for k in range(2):
            for i in range(3):
                for j in range(3):
                    x = 0.0
                    res = 0.0
                    for m in range(3):
                        for r in range(3):
                            x += self.Vinv[3 * i + m] * self.Vinv[3 * j + r] * e[k][3 * m + r]
                            res += self.W[3 * i + m] * self.W[3 * j + r] * e[k][3 * m + r]
                    tc[k][3 * i + j] = x
                    xc[k][3 * i + j] = res
        # S(x3) = S0 + S1 x3 + S2 x3^2 (4 x 4, row-major), rows (a2 a1 a0 0), (0 a2 a1 a0), (b2 b1 b0 0),
        # (0 b2 b1 b0), with a_p = sum_j xc[0][3 p + j] x3^j: S_j in Sq[16 j ..]
        for i in range(48):
            Sq[i] = 0.0
        for k in range(2):
            for r in range(2):                  # the row of equation k shifted by r
                for m in range(3):              # power p = 2 - m of x2 in column m + r
                    for j in range(3):
                        Sq[16 * j + 4 * (2 * k + r) + m + r] = xc[k][3 * (2 - m) + j]
        info = quadratic_pencil_eigenvalues(Sq, Sq + 16, Sq + 32, 4, A, B, ar, ai, be, lw, LWORK, col, piv,
                                            S2_RCOND, NULL, 0)
        if info != 0:
            uncertain[0] = True
            return 1
        mat3_mul(Rd, self.RMt, RdM)
        for s in range(8):
            if not (fabs(be[s]) > 0.0):
                continue
            x = ar[s] / be[s]
            if not (fabs(ai[s] / be[s]) <= IMAG_TOL * (1.0 + fabs(x))):
                continue
            any_real = True
            t3 = 2.0 * atan(x)                  # t3' (from the offset)
            c3 = cos(t3)
            s3 = sin(t3)
            for k in range(2):
                for i in range(3):
                    coef[k][i] = tc[k][3 * i] + tc[k][3 * i + 1] * c3 + tc[k][3 * i + 2] * s3
            strong = 0 if hypot(coef[0][1], coef[0][2]) >= hypot(coef[1][1], coef[1][2]) else 1
            if not cos_sin_equation(coef[strong][1], coef[strong][2], -coef[strong][0], ref[1] - self.delta[0],
                                    t2c):
                continue
            for w in range(2):
                t2 = t2c[w]
                other = coef[1 - strong][0] + coef[1 - strong][1] * cos(t2) + coef[1 - strong][2] * sin(t2)
                if not (fabs(other) <= OTHER_TOL):
                    continue
                qc[1] = t2 + self.delta[0]
                qc[2] = t3 + self.delta[1]
                self._f(qc[1], qc[2], f)
                if hypot(pp[0], pp[1]) > 1e-12:     # the wrist centre off axis 1 (scaled units)
                    q1 = atan2(pp[1], pp[0]) - atan2(f[1], f[0])
                else:
                    q1 = ref[0]
                qc[0] = q1
                # the wrist: R123 = R(L1 Z1 L2 Z2 L3 Z3) R0^T, R_w = R123^T R_d R_M^T
                _chain3(self.Ls, qc, T, X)
                for i in range(3):
                    for j in range(3):
                        R[3 * i + j] = T[4 * i + j]
                mat3_mul(R, self.R0t, R123)
                mat3T_mul(R123, RdM, Rw)
                mat3_vec(Rw, self.z[2], t6)
                two_axes(self.z[0], self.z[1], self.z[2], t6, ref[3], q4, q5)
                mat3_vec(Rw, self.x6, v)
                for k in range(2):
                    qc[3] = q4[k]
                    qc[4] = q5[k]
                    rodrigues(self.z[0], q4[k], R4)
                    rodrigues(self.z[1], q5[k], R5)
                    mat3_mul(R4, R5, R45)
                    mat3T_vec(R45, v, x6t)
                    qc[5] = angle_about(self.z[2], self.x6, x6t, 0.0)
                    for i in range(6):
                        nw[i] = qc[i]
                    res = newton_polish(self.chain.L, self.rev, self.scale, Rd, pd, nw, work)
                    if nb < NB and res < CANDIDATE_TOL:
                        for i in range(6):
                            Q[6 * nb + i] = nw[i]
                        geometric[nb] = True
                        nb += 1
        i = wrap_branches(Q, geometric, valid, ref, self.lo, self.hi, self.rev, NB, 6, self.limit_tol)
        if i == 0:
            return 0
        if i == 2:
            return 3
        uncertain[0] = any_real
        return 1 if any_real else 2


cdef inline void _chain3(double Ls[3][16], const double* q, double* T, double* X) noexcept nogil:
    """T = L_1 Z(q_1) L_2 Z(q_2) L_3 Z(q_3) (rotation only is used; lengths scaled)."""
    cdef int i, j, k
    cdef double c, s, a, b
    for i in range(16):
        T[i] = Ls[0][i]
    for k in range(3):
        c = cos(q[k])
        s = sin(q[k])
        for i in range(4):          # T <- T Z(q_k): columns 0, 1 mix
            a = T[4 * i]
            b = T[4 * i + 1]
            T[4 * i] = c * a + s * b
            T[4 * i + 1] = -s * a + c * b
        if k < 2:
            tf_mul(T, Ls[k + 1], X)
            for i in range(16):
                T[i] = X[i]


def chain_tool(La):
    """The tool pose at q = 0 from the chain's fixed transforms (n+1, 4, 4)."""
    out = np.eye(4)
    for Lk in La:
        out = out @ Lk
    return out
