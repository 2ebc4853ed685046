/* The body of crba_walk.h's walk, included once per lane type (no include guard on purpose). Defined by
   the includer: RK_WALK (the function's name), RK_T (a lane group: double, or a GCC vector of RK_W
   doubles), RK_W, RK_LOAD(p) (RK_W lanes from p), RK_STORE(p, v), RK_SPLAT(x), RK_LANE(v, k); undefined
   again at the end, ready for the next lane type.

   Lanes b0 .. b0 + RK_W - 1 of a block: the composite bodies, tip to base, then the columns of M. */
RK_CRBA_INLINE void RK_WALK(double* S, const unsigned char* rev, int n, const double* mass,
                            const double* com, const double* inertia, const double* beyond, double* M,
                            Py_ssize_t b0, Py_ssize_t B, Py_ssize_t PJ)
{
    const Py_ssize_t nn = (Py_ssize_t)n * n;
    int i, j, k;
    /* the composite body of joints i..n-1 about frame i's origin in its axes, held from joint to joint:
       first moment h = m c and the rotational inertia about the origin I (xx, yy, zz, xy, xz, yz) */
    RK_T h0, h1, h2, I0, I1, I2, I3, I4, I5;
    h0 = h1 = h2 = I0 = I1 = I2 = I3 = I4 = I5 = RK_SPLAT(0.0);
    for (i = n - 1; i >= 0; i--) {
        double* X = S + B * PJ * i + b0;
        double mi = mass[i], mc = beyond[i];
        double c0 = com[3 * i], c1 = com[3 * i + 1], c2 = com[3 * i + 2];
        double H0 = mi * c0, H1 = mi * c1, H2 = mi * c2;
        double O0 = inertia[9 * i] + ((H1 * c1) + (H2 * c2));
        double O1 = inertia[9 * i + 4] + ((H0 * c0) + (H2 * c2));
        double O2 = inertia[9 * i + 8] + ((H0 * c0) + (H1 * c1));
        double O3 = inertia[9 * i + 1] - (H0 * c1);
        double O4 = inertia[9 * i + 2] - (H0 * c2);
        double O5 = inertia[9 * i + 5] - (H1 * c2);
        /* body i alone about frame i's origin: h = m c, I_o = I_c + m (|c|^2 E - c c^T); the composite
           beyond it (mc: its mass, q-independent) merged when it has mass */
        if (i == n - 1 || mc == 0.0) {
            h0 = RK_SPLAT(H0); h1 = RK_SPLAT(H1); h2 = RK_SPLAT(H2);
            I0 = RK_SPLAT(O0); I1 = RK_SPLAT(O1); I2 = RK_SPLAT(O2);
            I3 = RK_SPLAT(O3); I4 = RK_SPLAT(O4); I5 = RK_SPLAT(O5);
        } else {
            /* the child composite into this frame with the child's X_{i+1} = (R, p): u = R h, R J R^T
               (K = J R^T, then the upper half), moved to this frame's origin (its points at p + r):
               + 2 (p.u) E - p u^T - u p^T + mc (|p|^2 E - p p^T); then this body's own part added */
            const double* C = X + B * PJ;
            RK_T r0 = RK_LOAD(C), r1 = RK_LOAD(C + B), r2 = RK_LOAD(C + 2 * B);
            RK_T r3 = RK_LOAD(C + 3 * B), r4 = RK_LOAD(C + 4 * B), r5 = RK_LOAD(C + 5 * B);
            RK_T r6 = RK_LOAD(C + 6 * B), r7 = RK_LOAD(C + 7 * B), r8 = RK_LOAD(C + 8 * B);
            RK_T p0 = RK_LOAD(C + 9 * B), p1 = RK_LOAD(C + 10 * B), p2 = RK_LOAD(C + 11 * B);
            RK_T u0 = ((r0 * h0) + (r1 * h1)) + (r2 * h2);
            RK_T u1 = ((r3 * h0) + (r4 * h1)) + (r5 * h2);
            RK_T u2 = ((r6 * h0) + (r7 * h1)) + (r8 * h2);
            RK_T J0 = I0, J4 = I1, J8 = I2, J1 = I3, J2 = I4, J5 = I5;
            RK_T K0 = ((J0 * r0) + (J1 * r1)) + (J2 * r2), K1 = ((J0 * r3) + (J1 * r4)) + (J2 * r5);
            RK_T K2 = ((J0 * r6) + (J1 * r7)) + (J2 * r8);
            RK_T K3 = ((J1 * r0) + (J4 * r1)) + (J5 * r2), K4 = ((J1 * r3) + (J4 * r4)) + (J5 * r5);
            RK_T K5 = ((J1 * r6) + (J4 * r7)) + (J5 * r8);
            RK_T K6 = ((J2 * r0) + (J5 * r1)) + (J8 * r2), K7 = ((J2 * r3) + (J5 * r4)) + (J8 * r5);
            RK_T K8 = ((J2 * r6) + (J5 * r7)) + (J8 * r8);
            RK_T y0 = p0 * u0, y1 = p1 * u1, y2 = p2 * u2;
            RK_T x0 = mc * p0, x1 = mc * p1, x2 = mc * p2;
            h0 = H0 + (u0 + x0);
            h1 = H1 + (u1 + x1);
            h2 = H2 + (u2 + x2);
            I0 = O0 + (((((r0 * K0) + (r1 * K3)) + (r2 * K6)) + (2.0 * (y1 + y2))) + ((x1 * p1) + (x2 * p2)));
            I1 = O1 + (((((r3 * K1) + (r4 * K4)) + (r5 * K7)) + (2.0 * (y0 + y2))) + ((x0 * p0) + (x2 * p2)));
            I2 = O2 + (((((r6 * K2) + (r7 * K5)) + (r8 * K8)) + (2.0 * (y0 + y1))) + ((x0 * p0) + (x1 * p1)));
            I3 = O3 + (((((r0 * K1) + (r1 * K4)) + (r2 * K7)) - ((p0 * u1) + (u0 * p1))) - (x0 * p1));
            I4 = O4 + (((((r0 * K2) + (r1 * K5)) + (r2 * K8)) - ((p0 * u2) + (u0 * p2))) - (x0 * p2));
            I5 = O5 + (((((r3 * K2) + (r4 * K5)) + (r5 * K8)) - ((p1 * u2) + (u1 * p2))) - (x1 * p2));
        }
        /* what the columns read: h_x, h_y, I_zz, I_xz, I_yz (rows 12, 13, 17, 19, 20) */
        RK_STORE(X + 12 * B, h0); RK_STORE(X + 13 * B, h1); RK_STORE(X + 17 * B, I2);
        RK_STORE(X + 19 * B, I4); RK_STORE(X + 20 * B, I5);
    }
    /* column i: the force and moment (about frame i's origin) a unit motion of joint i asks of composite
       body i, carried down to the base in registers; entry (j, i) is its component along joint j */
    for (i = 0; i < n; i++) {
        const double* X = S + B * PJ * i + b0;
        double cm = mass[i] + beyond[i];
        RK_T f0, f1, f2, n0, n1, n2, e;
        if (rev[i]) {
            /* w = z, v_origin = 0: f = z x h, n = I_o z */
            f0 = -RK_LOAD(X + 13 * B); f1 = RK_LOAD(X + 12 * B); f2 = RK_SPLAT(0.0);
            n0 = RK_LOAD(X + 19 * B); n1 = RK_LOAD(X + 20 * B); n2 = RK_LOAD(X + 17 * B);
            e = n2;
        } else {
            /* w = 0, v = z: f = m z, n = h x z */
            f0 = RK_SPLAT(0.0); f1 = RK_SPLAT(0.0); f2 = RK_SPLAT(cm);
            n0 = RK_LOAD(X + 13 * B); n1 = -RK_LOAD(X + 12 * B); n2 = RK_SPLAT(0.0);
            e = f2;
        }
        for (k = 0; k < RK_W; k++)
            M[nn * (b0 + k) + (Py_ssize_t)n * i + i] = RK_LANE(e, k);
        for (j = i - 1; j >= 0; j--) {
            /* f, n into frame j with the child's X_{j+1} = (R, p): R f, R n + p x (R f) */
            const double* C = S + B * PJ * (j + 1) + b0;
            if (j == 0 && rev[0]) {
                /* the last step, to a revolute base joint: only n's z is needed (the same expressions
                   as in the full step, so the same bits) */
                RK_T x0 = ((RK_LOAD(C) * f0) + (RK_LOAD(C + B) * f1)) + (RK_LOAD(C + 2 * B) * f2);
                RK_T x1 = ((RK_LOAD(C + 3 * B) * f0) + (RK_LOAD(C + 4 * B) * f1)) + (RK_LOAD(C + 5 * B) * f2);
                n2 = (((RK_LOAD(C + 6 * B) * n0) + (RK_LOAD(C + 7 * B) * n1)) + (RK_LOAD(C + 8 * B) * n2))
                     + ((RK_LOAD(C + 9 * B) * x1) - (RK_LOAD(C + 10 * B) * x0));
            } else if (j == 0) {
                /* to a prismatic base joint: only f's z */
                f2 = ((RK_LOAD(C + 6 * B) * f0) + (RK_LOAD(C + 7 * B) * f1)) + (RK_LOAD(C + 8 * B) * f2);
            } else {
                RK_T r0 = RK_LOAD(C), r1 = RK_LOAD(C + B), r2 = RK_LOAD(C + 2 * B);
                RK_T r3 = RK_LOAD(C + 3 * B), r4 = RK_LOAD(C + 4 * B), r5 = RK_LOAD(C + 5 * B);
                RK_T r6 = RK_LOAD(C + 6 * B), r7 = RK_LOAD(C + 7 * B), r8 = RK_LOAD(C + 8 * B);
                RK_T p0 = RK_LOAD(C + 9 * B), p1 = RK_LOAD(C + 10 * B), p2 = RK_LOAD(C + 11 * B);
                RK_T x0 = ((r0 * f0) + (r1 * f1)) + (r2 * f2);
                RK_T x1 = ((r3 * f0) + (r4 * f1)) + (r5 * f2);
                RK_T x2 = ((r6 * f0) + (r7 * f1)) + (r8 * f2);
                RK_T y0 = (((r0 * n0) + (r1 * n1)) + (r2 * n2)) + ((p1 * x2) - (p2 * x1));
                RK_T y1 = (((r3 * n0) + (r4 * n1)) + (r5 * n2)) + ((p2 * x0) - (p0 * x2));
                RK_T y2 = (((r6 * n0) + (r7 * n1)) + (r8 * n2)) + ((p0 * x1) - (p1 * x0));
                f0 = x0; f1 = x1; f2 = x2;
                n0 = y0; n1 = y1; n2 = y2;
            }
            e = rev[j] ? n2 : f2;
            for (k = 0; k < RK_W; k++) {
                M[nn * (b0 + k) + (Py_ssize_t)n * j + i] = RK_LANE(e, k);
                M[nn * (b0 + k) + (Py_ssize_t)n * i + j] = RK_LANE(e, k);
            }
        }
    }
}

#undef RK_WALK
#undef RK_T
#undef RK_W
#undef RK_LOAD
#undef RK_SPLAT
#undef RK_LANE
#undef RK_STORE
