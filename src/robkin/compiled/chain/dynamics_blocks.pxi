# Included by dynamics.pyx: the recursive Newton-Euler and composite-rigid-body walks over a block of up
# to BLOCK configurations at once.
#
# Every per-configuration quantity is stored structure-of-arrays, X[BLOCK * k + b] = component k of
# configuration b, and every step is a loop over b with the same operations in the same order for each b,
# which the compiler turns into SIMD code (no fused multiply-adds: setup.py builds with
# -ffp-contract=off). A single configuration is a block of one, so a batch equals its single calls bit for
# bit. The one exception to the lane loops is the mass matrix's walk after its transforms (crba_walk.h, C):
# it carries each composite body and column down the chain in registers, 4 lanes to a GCC vector, with the
# same operations per lane in the same order, so the same bits.
#
# LANE INDEX: the lane loops count with a 64-bit index (Py_ssize_t). Python's own CFLAGS hold -fwrapv, under
# which an int index such as BLOCK * 3 + b may wrap before it is widened for the address; GCC then sees
# the accesses as gathers/scatters, cannot rule out that a load from the scratch and a store into it
# overlap, and leaves the loop scalar (the CRBA's composite merge ran scalar that way).
#
# Notation per joint i: X_i = L_i Z_i(q_i) = (R, p), the parent -> child transform; body i's mass
# m, centre c and inertia I (about c) are in its own frame.

from robkin.compiled.chain.fk cimport rk_prefetch_part   # a range of cache lines asked for writing (a hint)


cdef extern from "chain/crba_walk.h" nogil:
    # the mass matrix's composite bodies and columns, in C: lane groups held in registers (see the header)
    void rk_crba_walk(double* S, const unsigned char* rev, int n, int m, const double* mass, const double* com,
                      const double* inertia, const double* beyond, double* M, Py_ssize_t lanes,
                      Py_ssize_t per_joint)


cdef enum:
    # configurations walked together; the largest per-block scratch (CRBA: 21 n x 32 doubles, ~38 kB at
    # n = 7) stays in L2, and 32 lanes are 4-8 SIMD vectors: the FK kernels' measured choice
    BLOCK = 32
    # doubles of scratch per joint and lane: R (9), p (3), then F and T (RNEA, 6) or the composite body
    # h, I_o (CRBA, 9)
    PER_JOINT = 21


cdef inline void block_transforms(const double* L, const unsigned char* rev, int n, const double* Q, int m,
                                  double* S) noexcept nogil:
    """X_i = (R, p) of every joint at the block's configurations: S[BLOCK * (PER_JOINT * i + k) + b]
    holds R's 9 entries (k < 9, row-major) and p (k = 9..11)."""
    cdef double qb[BLOCK]
    cdef double sb[BLOCK]
    cdef double cb[BLOCK]
    cdef const double* Li
    cdef double* X
    cdef int i, r
    cdef Py_ssize_t b   # lane index: 64-bit, see LANE INDEX below
    for i in range(n):
        Li = L + 16 * i
        X = S + BLOCK * PER_JOINT * i
        for b in range(m):
            qb[b] = Q[n * b + i]
        if rev[i]:
            if m == 1:
                rk_sincos_one(qb[0], sb, cb)
            else:
                rk_sincos_array(qb, sb, cb, m)
            for r in range(3):
                for b in range(m):
                    X[BLOCK * (3 * r) + b] = Li[4 * r] * cb[b] + Li[4 * r + 1] * sb[b]
                    X[BLOCK * (3 * r + 1) + b] = Li[4 * r + 1] * cb[b] - Li[4 * r] * sb[b]
                    X[BLOCK * (3 * r + 2) + b] = Li[4 * r + 2]
                    X[BLOCK * (9 + r) + b] = Li[4 * r + 3]
        else:
            for r in range(3):
                for b in range(m):
                    X[BLOCK * (3 * r) + b] = Li[4 * r]
                    X[BLOCK * (3 * r + 1) + b] = Li[4 * r + 1]
                    X[BLOCK * (3 * r + 2) + b] = Li[4 * r + 2]
                    X[BLOCK * (9 + r) + b] = Li[4 * r + 3] + Li[4 * r + 2] * qb[b]


cdef inline void rnea_block(const double* L, const unsigned char* rev, int n, const double* mass,
                            const double* com, const double* inertia, const double* Q, const double* QD,
                            const double* QDD, int m, const double* g, double* S, double* TAU) noexcept nogil:
    """Joint torques/forces TAU (m x n) at the block's configurations Q, QD, QDD (m x n, row-major; QD and
    QDD NULL for zero: then the velocity terms, all exactly zero, are skipped), gravity g (3,) in the base
    frame. S: scratch of BLOCK * PER_JOINT * n doubles."""
    cdef double w0[BLOCK]
    cdef double w1[BLOCK]
    cdef double w2[BLOCK]
    cdef double d0[BLOCK]
    cdef double d1[BLOCK]
    cdef double d2[BLOCK]
    cdef double a0[BLOCK]
    cdef double a1[BLOCK]
    cdef double a2[BLOCK]
    cdef double vq[BLOCK]
    cdef double aq[BLOCK]
    cdef double f0[BLOCK]
    cdef double f1[BLOCK]
    cdef double f2[BLOCK]
    cdef double n0[BLOCK]
    cdef double n1[BLOCK]
    cdef double n2[BLOCK]
    cdef double r0, r1, r2, r3, r4, r5, r6, r7, r8, p0, p1, p2
    cdef double u0, u1, u2, t0, t1, t2, x0, x1, x2, y0, y1, y2, z0, z1, z2
    cdef double c0, c1, c2, mi, I0, I1, I2, I3, I4, I5, I6, I7, I8
    cdef bint moving = QD != NULL or QDD != NULL
    cdef double* X
    cdef const double* C
    cdef int i
    cdef Py_ssize_t b
    block_transforms(L, rev, n, Q, m, S)
    for b in range(m):
        w0[b] = 0.0; w1[b] = 0.0; w2[b] = 0.0
        d0[b] = 0.0; d1[b] = 0.0; d2[b] = 0.0
        a0[b] = -g[0]; a1[b] = -g[1]; a2[b] = -g[2]   # gravity as a fictitious upward acceleration
    for i in range(n):
        X = S + BLOCK * PER_JOINT * i
        for b in range(m):
            vq[b] = 0.0 if QD == NULL else QD[n * b + i]
            aq[b] = 0.0 if QDD == NULL else QDD[n * b + i]
        mi = mass[i]
        c0 = com[3 * i]; c1 = com[3 * i + 1]; c2 = com[3 * i + 2]
        I0 = inertia[9 * i]; I1 = inertia[9 * i + 1]; I2 = inertia[9 * i + 2]
        I3 = inertia[9 * i + 3]; I4 = inertia[9 * i + 4]; I5 = inertia[9 * i + 5]
        I6 = inertia[9 * i + 6]; I7 = inertia[9 * i + 7]; I8 = inertia[9 * i + 8]
        if not moving:
            # at rest: only the acceleration standing for gravity is carried, R^T a, and F = m a, T = 0
            for b in range(m):
                x0 = X[b] * a0[b] + X[BLOCK * 3 + b] * a1[b] + X[BLOCK * 6 + b] * a2[b]
                x1 = X[BLOCK + b] * a0[b] + X[BLOCK * 4 + b] * a1[b] + X[BLOCK * 7 + b] * a2[b]
                x2 = X[BLOCK * 2 + b] * a0[b] + X[BLOCK * 5 + b] * a1[b] + X[BLOCK * 8 + b] * a2[b]
                a0[b] = x0; a1[b] = x1; a2[b] = x2
                X[BLOCK * 12 + b] = mi * x0
                X[BLOCK * 13 + b] = mi * x1
                X[BLOCK * 14 + b] = mi * x2
                X[BLOCK * 15 + b] = 0.0
                X[BLOCK * 16 + b] = 0.0
                X[BLOCK * 17 + b] = 0.0
            continue
        for b in range(m):
            r0 = X[b]; r1 = X[BLOCK + b]; r2 = X[BLOCK * 2 + b]
            r3 = X[BLOCK * 3 + b]; r4 = X[BLOCK * 4 + b]; r5 = X[BLOCK * 5 + b]
            r6 = X[BLOCK * 6 + b]; r7 = X[BLOCK * 7 + b]; r8 = X[BLOCK * 8 + b]
            p0 = X[BLOCK * 9 + b]; p1 = X[BLOCK * 10 + b]; p2 = X[BLOCK * 11 + b]
            # acceleration of this frame's origin in the parent frame: a + dw x p + w x (w x p)
            u0 = w1[b] * p2 - w2[b] * p1
            u1 = w2[b] * p0 - w0[b] * p2
            u2 = w0[b] * p1 - w1[b] * p0
            x0 = a0[b] + (d1[b] * p2 - d2[b] * p1) + (w1[b] * u2 - w2[b] * u1)
            x1 = a1[b] + (d2[b] * p0 - d0[b] * p2) + (w2[b] * u0 - w0[b] * u2)
            x2 = a2[b] + (d0[b] * p1 - d1[b] * p0) + (w0[b] * u1 - w1[b] * u0)
            # into this frame: R^T
            a0[b] = r0 * x0 + r3 * x1 + r6 * x2
            a1[b] = r1 * x0 + r4 * x1 + r7 * x2
            a2[b] = r2 * x0 + r5 * x1 + r8 * x2
            y0 = r0 * w0[b] + r3 * w1[b] + r6 * w2[b]
            y1 = r1 * w0[b] + r4 * w1[b] + r7 * w2[b]
            y2 = r2 * w0[b] + r5 * w1[b] + r8 * w2[b]
            z0 = r0 * d0[b] + r3 * d1[b] + r6 * d2[b]
            z1 = r1 * d0[b] + r4 * d1[b] + r7 * d2[b]
            z2 = r2 * d0[b] + r5 * d1[b] + r8 * d2[b]
            w0[b] = y0; w1[b] = y1; w2[b] = y2
            d0[b] = z0; d1[b] = z1; d2[b] = z2
        if rev[i]:
            for b in range(m):
                d0[b] = d0[b] + w1[b] * vq[b]     # w_parent x (z qd), then the joint's own z qdd
                d1[b] = d1[b] - w0[b] * vq[b]
                d2[b] = d2[b] + aq[b]
                w2[b] = w2[b] + vq[b]
        else:
            for b in range(m):
                a0[b] = a0[b] + 2.0 * w1[b] * vq[b]   # Coriolis 2 w x (z qd), then z qdd
                a1[b] = a1[b] - 2.0 * w0[b] * vq[b]
                a2[b] = a2[b] + aq[b]
        for b in range(m):
            # force at the centre: m (a + dw x c + w x (w x c))
            u0 = w1[b] * c2 - w2[b] * c1
            u1 = w2[b] * c0 - w0[b] * c2
            u2 = w0[b] * c1 - w1[b] * c0
            X[BLOCK * 12 + b] = mi * (a0[b] + (d1[b] * c2 - d2[b] * c1) + (w1[b] * u2 - w2[b] * u1))
            X[BLOCK * 13 + b] = mi * (a1[b] + (d2[b] * c0 - d0[b] * c2) + (w2[b] * u0 - w0[b] * u2))
            X[BLOCK * 14 + b] = mi * (a2[b] + (d0[b] * c1 - d1[b] * c0) + (w0[b] * u1 - w1[b] * u0))
            # moment about the centre: I dw + w x (I w)
            u0 = I0 * w0[b] + I1 * w1[b] + I2 * w2[b]
            u1 = I3 * w0[b] + I4 * w1[b] + I5 * w2[b]
            u2 = I6 * w0[b] + I7 * w1[b] + I8 * w2[b]
            X[BLOCK * 15 + b] = (I0 * d0[b] + I1 * d1[b] + I2 * d2[b]) + (w1[b] * u2 - w2[b] * u1)
            X[BLOCK * 16 + b] = (I3 * d0[b] + I4 * d1[b] + I5 * d2[b]) + (w2[b] * u0 - w0[b] * u2)
            X[BLOCK * 17 + b] = (I6 * d0[b] + I7 * d1[b] + I8 * d2[b]) + (w0[b] * u1 - w1[b] * u0)
    # backward: f, n = force and moment (about frame i's origin) that body i-1 exerts on body i (zeroed
    # first only so that the compiler sees them written: the last joint's step never reads them)
    for b in range(m):
        f0[b] = 0.0; f1[b] = 0.0; f2[b] = 0.0
        n0[b] = 0.0; n1[b] = 0.0; n2[b] = 0.0
    for i in range(n - 1, -1, -1):
        c0 = com[3 * i]; c1 = com[3 * i + 1]; c2 = com[3 * i + 2]
        X = S + BLOCK * PER_JOINT * i
        if i < n - 1:
            C = S + BLOCK * PER_JOINT * (i + 1)
            for b in range(m):
                # the child's f, n into this frame with the child's X: R f, R n + p x (R f)
                r0 = C[b]; r1 = C[BLOCK + b]; r2 = C[BLOCK * 2 + b]
                r3 = C[BLOCK * 3 + b]; r4 = C[BLOCK * 4 + b]; r5 = C[BLOCK * 5 + b]
                r6 = C[BLOCK * 6 + b]; r7 = C[BLOCK * 7 + b]; r8 = C[BLOCK * 8 + b]
                p0 = C[BLOCK * 9 + b]; p1 = C[BLOCK * 10 + b]; p2 = C[BLOCK * 11 + b]
                x0 = r0 * f0[b] + r1 * f1[b] + r2 * f2[b]
                x1 = r3 * f0[b] + r4 * f1[b] + r5 * f2[b]
                x2 = r6 * f0[b] + r7 * f1[b] + r8 * f2[b]
                y0 = r0 * n0[b] + r1 * n1[b] + r2 * n2[b] + (p1 * x2 - p2 * x1)
                y1 = r3 * n0[b] + r4 * n1[b] + r5 * n2[b] + (p2 * x0 - p0 * x2)
                y2 = r6 * n0[b] + r7 * n1[b] + r8 * n2[b] + (p0 * x1 - p1 * x0)
                t0 = X[BLOCK * 12 + b]; t1 = X[BLOCK * 13 + b]; t2 = X[BLOCK * 14 + b]
                f0[b] = t0 + x0
                f1[b] = t1 + x1
                f2[b] = t2 + x2
                n0[b] = X[BLOCK * 15 + b] + (c1 * t2 - c2 * t1) + y0
                n1[b] = X[BLOCK * 16 + b] + (c2 * t0 - c0 * t2) + y1
                n2[b] = X[BLOCK * 17 + b] + (c0 * t1 - c1 * t0) + y2
        else:
            for b in range(m):
                t0 = X[BLOCK * 12 + b]; t1 = X[BLOCK * 13 + b]; t2 = X[BLOCK * 14 + b]
                f0[b] = t0
                f1[b] = t1
                f2[b] = t2
                n0[b] = X[BLOCK * 15 + b] + (c1 * t2 - c2 * t1)
                n1[b] = X[BLOCK * 16 + b] + (c2 * t0 - c0 * t2)
                n2[b] = X[BLOCK * 17 + b] + (c0 * t1 - c1 * t0)
        if rev[i]:
            for b in range(m):
                TAU[n * b + i] = n2[b]
        else:
            for b in range(m):
                TAU[n * b + i] = f2[b]


cdef inline void crba_block(const double* L, const unsigned char* rev, int n, const double* mass,
                            const double* com, const double* inertia, const double* beyond, const double* Q,
                            int m, double* S, double* M) noexcept nogil:
    """Mass matrices M (m x n x n, row-major) at the block's configurations Q (m x n). ``beyond[i]`` is the
    mass of bodies i+1..n-1 (q-independent, as the composite masses are: never stored per lane).
    S: scratch of BLOCK * PER_JOINT * n doubles: the transforms (``block_transforms``), then the
    composite bodies in rows 12..20 of each joint, and the columns of M (``rk_crba_walk``, crba_walk.h:
    Featherstone's composite-rigid-body algorithm with each composite body a spatial inertia about its
    frame's origin, lanes held in registers)."""
    # the block's matrices are written lane by lane, n * n doubles apart: a batch's output is fresh memory,
    # so ask for its cache lines now, and they arrive while the transforms and the composite bodies are
    # computed (without, the scattered stores waited on them: a quarter of the walk)
    rk_prefetch_part(M, <Py_ssize_t>m * n * n * 8, 0, 1)
    block_transforms(L, rev, n, Q, m, S)
    # the composite bodies and the columns: crba_walk.h
    rk_crba_walk(S, rev, n, m, mass, com, inertia, beyond, M, BLOCK, PER_JOINT)
