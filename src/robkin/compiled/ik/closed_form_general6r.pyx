"""Compiled closed-form IK of any revolute 6R arm: every real solution (up to 16), by elimination.

The kernel behind ``kinematics.general6r.General6R``. The method is Raghavan and Roth's elimination as
Manocha and Canny solve it (a matrix polynomial's eigenvalues), built numerically per target:

1. The loop. With the compiled chain T(q) = L_1 Z(q_1) L_2 ... L_6 Z(q_6) L_7 (``fk.pxd``), the target
   closes a loop of six joint rotations Z and six fixed links K: K_i = L_{i+1} for i < 6 and
   K_6 = L_7 T^-1 L_1, with Z(q_1) K_1 ... Z(q_6) K_6 = I. Any cyclic shift of the loop, and its
   inverse (joints backwards, angles negated), is a loop of the same form: the *formulation* (a shift
   and a direction, chosen per robot by the Python side) names the joints a, b, c, d, e, f in loop order.
2. The equations. Z_a K_a Z_b K_b Z_c K_c carries the line of axis d (z axis and origin of frame d,
   invariant under Z_d) to the same line as (K_d Z_e K_e Z_f K_f)^-1. Of the line (point p, direction
   l) take the 14 quantities p, l, p.p, p.l, p x l, (p.p) l - 2 (p.l) p: Raghavan and Roth showed both
   sides then stay linear in (1, cos, sin) of each joint angle. Each side's coefficients are read off
   exactly by trigonometric interpolation at three angles per joint (27 and 9 evaluations).
3. Elimination. The 8 non-constant products of joints e and f are eliminated by the left null space
   of their 14 x 8 coefficient block (a Householder QR): 6 equations in joints a, b, c remain. With
   x = tan(theta / 2) (each angle measured from a fixed random offset, so that no solution sits at
   x = infinity) they are quadratic in x_a, x_b, x_c; multiplied by x_b too, they are 12 equations
   M(x_a) v = 0 in the 12 monomials x_b^i x_c^j (i <= 3, j <= 2), M quadratic in x_a.
4. det M(x_a) = 0 is the degree-16 problem (24 with the 8 spurious roots x = +-i): the eigenvalues of
   the 24 x 24 companion matrix [[0, I], -M2^-1 [M0, M1]]. The spurious roots' eigenvectors are the
   arm's, the same for every target, so the Python side finds their invariant subspace once
   (``kinematics.general6r.spurious_complement``) and each target solves the 16 x 16 block on its
   orthonormal complement, by the small-matrix QR of ``hessenberg_qr.h`` (LAPACK ``dgeev`` where that
   does not converge); ``dggev`` on the 24 x 24 pencil when M2 is ill-conditioned (LAPACK through
   ``scipy.linalg.cython_lapack``: no linking, scipy exports it).
5. Back-substitution. Per real root: v is M(x_a)'s null vector (full-pivoting LU), whose monomial
   ratios give x_b and x_c; joints e, f from the eliminated equations (least squares on the QR);
   joint d from the remaining rotation. Each candidate is polished by Newton steps on the exact forward
   kinematics (the robot's own chain, not the loop) and wrapped into the limits; the verification and
   choice are the base class's (``nearest.pxd``).

Outcome codes: 0 a valid branch exists; 1 no branch converged although candidate roots existed, or the
elimination was rank-deficient at this target (``uncertain``: ``ik`` retries numerically); 2 no real
root (out of reach); 3 solutions exist but violate the joint limits.
"""

import numpy as np

cimport numpy as cnp
from libc.math cimport atan, atan2, cos, fabs, sin, INFINITY
from robkin.compiled.ik.closed_form_kernel cimport ClosedFormKernel
from robkin.compiled.chain.fk cimport Chain
from robkin.compiled.ik.elimination cimport (eliminate_block, line_quantities, move_line, null_vector,
                                          pair_angle, quadratic_pencil_eigenvalues, rz_mul, small_eigenvalues,
                                          solve_block, transform3)
from robkin.compiled.runtime.linalg cimport tf_inv, tf_mul
from robkin.compiled.ik.newton cimport CANDIDATE_TOL, newton_polish
from robkin.compiled.ik.subproblems cimport wrap_branches

cnp.import_array()

cdef enum:
    NB = 24         # branches per target: one per eigenvalue of the 24 x 24 pencil that may be real
    NP = 24         # the pencil's size
    LWORK = 1536    # LAPACK's workspace for it (64 n: room for its blocked algorithms)

# The work array's layout (doubles): _pencil fills F .. Mq, solve_one uses Rc, Vq, Mq and what follows
cdef enum:
    AT_F = 0                    # 14 x 27 LHS samples -> x-power coefficients
    AT_G = AT_F + 14 * 27       # 14 x 9 RHS samples
    AT_RC = AT_G + 14 * 9       # 14 x 9 RHS coefficients (1, cos, sin)^2; R of the QR in columns 1..8
    AT_PX = AT_RC + 14 * 9      # 14 x 27 LHS coefficients in x powers (after c0)
    AT_VQ = AT_PX + 14 * 27     # 14 x 8 Householder vectors (column-major by column)
    AT_MQ = AT_VQ + 14 * 8      # 3 x 12 x 12 M0, M1, M2 (row-major)

#: An eigenvalue counts as a real root when |Im x| <= IMAG_TOL (1 + |x|): a double root (a target on
#: a singularity) splits into a pair with |Im| ~ sqrt(eps) ~ 1e-8; 1e-4 keeps those and anything the
#: Newton polish can still pull onto a true solution (spurious candidates then fail its check).
cdef double IMAG_TOL = 1e-4
#: the pivot ratio below which M2 counts as singular (use the generalised eigenproblem): the companion
#: matrix M2^-1 M0, M2^-1 M1 then loses more than half the digits
cdef double M2_RCOND = 1e-8
#: QR of the eliminated block: a column whose remaining norm is below RANK_TOL times the largest
#: makes the elimination rank-deficient at this target (a formulation's special case)
cdef double RANK_TOL = 1e-11

cdef double TWO_PI_3 = 2.0943951023931957


def eigenvalues(A):
    """The eigenvalues (n,) complex of the small square matrix A (n <= 32) by the kernel's own routine
    (``hessenberg_qr.h``, LAPACK where it does not converge): for tests."""
    cdef double[::1, :] a = np.array(A, dtype=np.float64, order="F", copy=True)
    cdef int n = a.shape[0]
    if a.shape[1] != n or not 0 < n <= 32:
        raise ValueError("eigenvalues: expected a square matrix of size 1 to 32")
    cdef double[::1] scratch = np.empty(n * n)
    cdef double[::1] wr = np.empty(n)
    cdef double[::1] wi = np.empty(n)
    cdef double[::1] lw = np.empty(64 * n)
    cdef int info
    with nogil:
        info = small_eigenvalues(&a[0, 0], n, n, &scratch[0], &wr[0], &wi[0], &lw[0], 64 * n)
    if info != 0:
        raise ArithmeticError(f"eigenvalues: LAPACK dgeev info {info}")
    return np.asarray(wr) + 1j * np.asarray(wi)


cdef class General6RKernel(ClosedFormKernel):
    """One formulation of the loop (see the module docstring) of one 6R robot."""

    cdef double Ls[7][16]          # the chain's fixed transforms, lengths divided by the robot's size
    cdef double Kin[5][16]         # their inverses K_i^-1 = L_{i+1}^-1 (i < 5)
    cdef int order[6]              # the joints a, b, c, d, e, f (0-based)
    cdef double sgn[6]             # +1 forward loop, -1 inverse loop (the loop angle is sgn q)
    cdef double delta[6]           # per loop position, the offset the half-angle variable is measured from
    cdef bint reverse
    cdef double W[9]               # samples at 0, 2pi/3, 4pi/3 -> (1 + x^2)-scaled coefficients of 1, x, x^2
    cdef double Vinv[9]            # samples -> coefficients of 1, cos, sin
    cdef bint deflate              # the spurious roots' invariant subspace is known: solve the 16 x 16
    cdef double complement[NP * (NP - 8)]  # its orthonormal complement (24 x 16, column-major)

    def __init__(self, Chain chain, limits, ref0, double scale, double limit_tol, L, int shift, bint reverse,
                 delta):
        super().__init__(chain, limits, [True] * 6, scale, limit_tol, ref0, NB, 8000)
        cdef int i, j, k
        Larr = np.array(L, dtype=np.float64)
        for i in range(7):
            for j in range(4):
                for k in range(4):
                    self.Ls[i][4 * j + k] = Larr[i, j, k] / (scale if (k == 3 and j < 3) else 1.0)
        for i in range(5):
            tf_inv(self.Ls[i + 1], self.Kin[i])
        seq = list(range(6)) if not reverse else list(range(5, -1, -1))
        seq = seq[shift:] + seq[:shift]
        d = np.asarray(delta, dtype=np.float64)
        for i in range(6):
            self.order[i] = seq[i]
            self.sgn[i] = -1.0 if reverse else 1.0
            self.delta[i] = d[i]
        self.reverse = reverse
        samples = TWO_PI_3 * np.arange(3)
        V = np.column_stack([np.ones(3), np.cos(samples), np.sin(samples)])        # V[k, m]: basis m at k
        Vi = np.linalg.inv(V)
        H = np.array([[1.0, 1.0, 0.0], [0.0, 0.0, 2.0], [1.0, -1.0, 0.0]])        # (1, c, s) -> (1, x, x^2)
        Wm = H @ Vi
        for i in range(3):
            for j in range(3):
                self.W[3 * i + j] = Wm[i, j]
                self.Vinv[3 * i + j] = Vi[i, j]

    def pencil(self, T):
        """The matrix polynomial M(x) = M0 + M1 x + M2 x^2 (3, 12, 12) of the target T (4 x 4, the
        robot's units), or None where the elimination is rank-deficient (step 3)."""
        cdef double[:, ::1] t = np.ascontiguousarray(T, dtype=np.float64)
        cdef double[::1] w = np.empty(self.work_size)
        cdef double K[96]
        cdef double tau[8]
        cdef double Rd[9]
        cdef double pd[3]
        cdef int i, j
        for i in range(3):
            pd[i] = t[i, 3]
            for j in range(3):
                Rd[3 * i + j] = t[i, j]
        if not self._pencil(Rd, pd, K, tau, &w[0]):
            return None
        return np.asarray(w[AT_MQ:AT_MQ + 432]).reshape(3, 12, 12).copy()

    def set_deflation(self, complement):
        """Solve the 16 x 16 problem on ``complement`` (24, 16), the orthonormal complement of the
        invariant subspace of the 8 spurious roots x = +-i of every target's companion matrix (computed
        by ``kinematics.general6r``); None: the full 24 x 24 problem."""
        cdef int i, j
        if complement is None:
            self.deflate = False
            return
        c = np.asarray(complement, dtype=np.float64)
        if c.shape != (NP, NP - 8):
            raise ValueError(f"set_deflation: expected a ({NP}, {NP - 8}) array, got {c.shape}")
        for j in range(NP - 8):
            for i in range(NP):
                self.complement[i + NP * j] = c[i, j]
        self.deflate = True

    cdef void _link(self, int pos, const double* K6, const double* K6inv, double* out) noexcept nogil:
        """The fixed link after loop position pos (of joint order[pos])."""
        cdef int j = self.order[pos], i, m
        cdef const double* src
        if not self.reverse:
            src = K6 if j == 5 else self.Ls[j + 1]
        else:                       # the inverse loop: joint j is followed by K_{j-1}^-1
            m = (j + 5) % 6
            src = K6inv if m == 5 else self.Kin[m]
        for i in range(16):
            out[i] = src[i]

    cdef bint _pencil(self, const double* Rd, const double* pd, double* K, double* tau,
                      double* work) noexcept nogil:
        """Steps 1-4 of the module docstring for the target (Rd, pd): the loop's six links in loop order
        into K (6 x 16), the eliminated block's QR (Householder vectors, ``tau`` (8), R) and
        M0, M1, M2 into ``work`` (see ``solve_one``'s layout). False when the eliminated block is
        rank-deficient at this target (no M then)."""
        cdef double T[16]
        cdef double Ti[16]
        cdef double K6[16]
        cdef double K6inv[16]
        cdef double Kdi[16]
        cdef double Kei[16]
        cdef double Kfi[16]
        cdef double X1[16]
        cdef double X2[16]
        cdef double X3[16]
        cdef double X4[16]
        cdef double pl[6]
        cdef double p0[3]
        cdef double l0[3]
        cdef double pa[3]
        cdef double la[3]
        cdef int i, j, k, r, c, I, Jp, Kp
        cdef double x, t, nrm, alpha, dotv, big
        cdef double* Ka = K
        cdef double* Kb = K + 16
        cdef double* Kc = K + 32
        cdef double* Kd = K + 48
        cdef double* Ke = K + 64
        cdef double* Kf = K + 80
        cdef double* F = work + AT_F
        cdef double* G = work + AT_G
        cdef double* Rc = work + AT_RC
        cdef double* Px = work + AT_PX
        cdef double* Vq = work + AT_VQ
        cdef double* Mq = work + AT_MQ
        # ---- 1. the loop's target link K_6 = L_7 T^-1 L_1 (scaled), and the six links in loop order
        for i in range(3):
            for j in range(3):
                T[4 * i + j] = Rd[3 * i + j]
            T[4 * i + 3] = pd[i] / self.scale
        T[12] = 0.0; T[13] = 0.0; T[14] = 0.0; T[15] = 1.0
        tf_inv(T, Ti)
        tf_mul(self.Ls[6], Ti, X1)
        tf_mul(X1, self.Ls[0], K6)
        tf_inv(K6, K6inv)
        self._link(0, K6, K6inv, Ka)
        self._link(1, K6, K6inv, Kb)
        self._link(2, K6, K6inv, Kc)
        self._link(3, K6, K6inv, Kd)
        self._link(4, K6, K6inv, Ke)
        self._link(5, K6, K6inv, Kf)
        tf_inv(Kd, Kdi)
        tf_inv(Ke, Kei)
        tf_inv(Kf, Kfi)
        # ---- 2. samples of both sides: LHS at 27 (a, b, c), RHS at 9 (e, f)
        for i in range(3):
            p0[i] = Kc[4 * i + 3]
            l0[i] = Kc[4 * i + 2]
        for i in range(3):
            rz_mul(self.sgn[0] * (TWO_PI_3 * i + self.delta[0]), Ka, X1)
            for j in range(3):
                rz_mul(self.sgn[1] * (TWO_PI_3 * j + self.delta[1]), Kb, X3)
                tf_mul(X1, X3, X2)
                for k in range(3):
                    t = self.sgn[2] * (TWO_PI_3 * k + self.delta[2])
                    pa[0] = cos(t) * p0[0] - sin(t) * p0[1]
                    pa[1] = sin(t) * p0[0] + cos(t) * p0[1]
                    pa[2] = p0[2]
                    la[0] = cos(t) * l0[0] - sin(t) * l0[1]
                    la[1] = sin(t) * l0[0] + cos(t) * l0[1]
                    la[2] = l0[2]
                    move_line(X2, pa, la, pl, pl + 3)
                    line_quantities(pl, pl + 3, F + 9 * i + 3 * j + k, 27)
        for i in range(3):
            p0[i] = Kdi[4 * i + 3]
            l0[i] = Kdi[4 * i + 2]
        for i in range(3):
            t = -self.sgn[4] * (TWO_PI_3 * i + self.delta[4])
            rz_mul(t, Kdi, X1)
            tf_mul(Kei, X1, X2)                   # Ke^-1 Rz(-phi_e) Kd^-1
            for j in range(3):
                rz_mul(-self.sgn[5] * (TWO_PI_3 * j + self.delta[5]), X2, X3)
                tf_mul(Kfi, X3, X4)
                for k in range(3):
                    pa[k] = X4[4 * k + 3]
                    la[k] = X4[4 * k + 2]
                line_quantities(pa, la, G + 3 * i + j, 9)
        # ---- 3. coefficients: RHS in (1, cos, sin)^2; LHS (minus the RHS constant) in x powers
        for r in range(14):
            for I in range(3):
                for Jp in range(3):
                    x = 0.0
                    for i in range(3):
                        for j in range(3):
                            x += self.Vinv[3 * I + i] * self.Vinv[3 * Jp + j] * G[9 * r + 3 * i + j]
                    Rc[9 * r + 3 * I + Jp] = x
        for r in range(14):
            for i in range(27):
                F[27 * r + i] -= Rc[9 * r]
            transform3(F + 27 * r, self.W, Px + 27 * r)
        # ---- Householder QR of the 14 x 8 block C8 = Rc[:, 1:]; Q^T applied to Px (14 x 27)
        if not eliminate_block(Rc, Px, Vq, tau, RANK_TOL):
            return False
        # ---- 4. M(x_a) = M0 + M1 x_a + M2 x_a^2 from the 6 remaining rows (8..13) of Q^T Px
        for i in range(3 * 144):
            Mq[i] = 0.0
        for r in range(6):
            for I in range(3):
                for Jp in range(3):
                    for Kp in range(3):
                        x = Px[27 * (8 + r) + 9 * I + 3 * Jp + Kp]
                        Mq[144 * I + 12 * r + 3 * Jp + Kp] = x
                        Mq[144 * I + 12 * (r + 6) + 3 * (Jp + 1) + Kp] = x
        return True

    cdef signed char solve_one(self, const double* Rd, const double* pd, const double* ref, double* Q,
                               unsigned char* valid, double* detail, unsigned char* uncertain,
                               double* work) noexcept nogil:
        cdef double K[96]
        cdef double X1[16]
        cdef double X2[16]
        cdef double X3[16]
        cdef double X4[16]
        cdef double pa[3]
        cdef double la[3]
        cdef double y[14]
        cdef double tau[8]
        cdef double m8[8]
        cdef double vnull[12]
        cdef double qc[6]
        cdef double th[6]
        cdef unsigned char geometric[NB]
        cdef int rp[12]
        cdef int cp[12]
        cdef int i, j, k, r, c, s, info, nroots = 0
        cdef double x, t, dotv, xr, xi, res
        cdef bint any_real = False
        cdef double* Ka = K
        cdef double* Kb = K + 16
        cdef double* Kc = K + 32
        cdef double* Kd = K + 48
        cdef double* Ke = K + 64
        cdef double* Kf = K + 80
        # work layout: _pencil's (AT_ above), then this method's own
        cdef double* Rc = work + AT_RC
        cdef double* Vq = work + AT_VQ
        cdef double* Mq = work + AT_MQ
        cdef double* Ap = Mq + 3 * 144            # 24 x 24 (column-major) pencil A
        cdef double* Bp = Ap + NP * NP            # 24 x 24 pencil B / LU of M2
        cdef double* ar = Bp + NP * NP            # alphar, alphai, beta (24 each)
        cdef double* ai = ar + NP
        cdef double* be = ai + NP
        cdef double* lw = be + NP                 # LAPACK workspace
        cdef double* Mx = lw + LWORK              # 12 x 12 M(x)
        cdef double* nw = Mx + 144                # Newton's scratch (6)
        cdef double* M0 = Mq
        cdef double* M1 = Mq + 144
        cdef double* M2 = Mq + 288
        cdef int* piv = rp
        detail[0] = INFINITY
        uncertain[0] = False
        if not self._pencil(Rd, pd, K, tau, work):
            uncertain[0] = True
            for s in range(NB):
                valid[s] = False
                for j in range(6):
                    Q[6 * s + j] = 0.0
            return 1
        # ---- eigenvalues of the quadratic pencil (companion + dgeev, or dggev when M2 is singular),
        # the 8 spurious roots x = +-i deflated when the robot's invariant subspace is known
        info = quadratic_pencil_eigenvalues(M0, M1, M2, 12, Ap, Bp, ar, ai, be, lw, LWORK, Mx, piv, M2_RCOND,
                                            <const double*>self.complement if self.deflate else NULL, NP - 8)
        if info != 0:
            uncertain[0] = True
            for s in range(NB):
                valid[s] = False
                for j in range(6):
                    Q[6 * s + j] = 0.0
            return 1
        # ---- 5. back-substitution per real root
        for s in range(NB):
            geometric[s] = False
            for j in range(6):
                Q[6 * s + j] = 0.0
        for s in range(NP):
            if not (fabs(be[s]) > 0.0):
                continue
            xr = ar[s] / be[s]
            xi = ai[s] / be[s]
            if not (fabs(xi) <= IMAG_TOL * (1.0 + fabs(xr))):
                continue
            any_real = True
            for i in range(144):
                Mx[i] = M0[i] + xr * (M1[i] + xr * M2[i])
            null_vector(Mx, 12, vnull, cp)
            th[0] = 2.0 * atan(xr)
            th[1] = pair_angle(vnull, 3, 3, 3, 3, 1)      # x_b: v[3 i + j] -> v[3 (i + 1) + j]
            th[2] = pair_angle(vnull, 1, 4, 2, 3, 1)      # x_c: v[3 i + j] -> v[3 i + j + 1]
            # joints e, f: C8 m8 = LHS(a, b, c) - c0, by the QR (Q^T, then R's back-substitution)
            rz_mul(self.sgn[0] * (th[0] + self.delta[0]), Ka, X1)
            rz_mul(self.sgn[1] * (th[1] + self.delta[1]), Kb, X3)
            tf_mul(X1, X3, X2)
            rz_mul(self.sgn[2] * (th[2] + self.delta[2]), Kc, X3)
            tf_mul(X2, X3, X4)                              # Lh = Z_a K_a Z_b K_b Z_c K_c
            for i in range(3):
                pa[i] = X4[4 * i + 3]
                la[i] = X4[4 * i + 2]
            line_quantities(pa, la, y, 1)
            for r in range(14):
                y[r] -= Rc[9 * r]                           # column 0: untouched by the QR
            solve_block(Rc, Vq, tau, y, m8)
            # m8: (1, ce, se) x (1, cf, sf) without the constant: cf, sf, ce, ce cf, ce sf, se, se cf, se sf
            th[4] = atan2(m8[5], m8[2])
            th[5] = atan2(m8[1], m8[0])
            # joint d: Rz(phi_d) = Lh^-1 Rh^-1 with Rh = K_d Z_e K_e Z_f K_f
            rz_mul(self.sgn[4] * (th[4] + self.delta[4]), Ke, X1)
            tf_mul(Kd, X1, X2)
            rz_mul(self.sgn[5] * (th[5] + self.delta[5]), Kf, X1)
            tf_mul(X2, X1, X3)                              # Rh
            tf_mul(X3, X4, X1)                              # Rh Lh = Rz(-phi_d)
            t = atan2(X1[1], X1[0])                         # phi_d
            for i in range(6):
                if i == 3:
                    qc[self.order[i]] = self.sgn[i] * t
                else:
                    qc[self.order[i]] = th[i] + self.delta[i]     # q = sgn phi, phi = sgn (th + delta)
            res = newton_polish(self.chain.L, self.rev, self.scale, Rd, pd, qc, nw)
            if nroots < NB and res < CANDIDATE_TOL:
                for j in range(6):
                    Q[6 * nroots + j] = qc[j]
                geometric[nroots] = True
                nroots += 1
        i = wrap_branches(Q, geometric, valid, ref, self.lo, self.hi, self.rev, NB, 6, self.limit_tol)
        if i == 0:
            return 0
        if i == 2:
            return 3
        uncertain[0] = any_real
        return 1 if any_real else 2
