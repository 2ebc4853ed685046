/* The body of crba_columns.h's column walk, included once per lane type (no include guard on purpose).
   Defined by the includer: RK_COLUMNS (the function's name), RK_T (a lane group: double, or a GCC
   vector of RK_W doubles), RK_W, RK_LOAD(p) (RK_W lanes from p), RK_SPLAT(x), RK_LANE(v, k). */

static inline void RK_COLUMNS(const double* S, const unsigned char* rev, int n, const double* mass,
                              const double* beyond, double* M, Py_ssize_t b0, Py_ssize_t B, Py_ssize_t PJ)
{
    const Py_ssize_t nn = (Py_ssize_t)n * n;
    int i, j, k;
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
