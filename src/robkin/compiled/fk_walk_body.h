/* The body of fk_walk.h's walk, included once per lane type (no include guard on purpose). Defined by
   the includer: RK_STEPS (the function's name), RK_T (a lane group: double, or a GCC vector of RK_W
   doubles), RK_W, RK_LOAD(p) (RK_W lanes from p), RK_STORE(p, v), RK_SPLAT(x), RK_LANE(v, k); undefined
   again at the end, ready for the next lane type.

   Lanes b0 .. b0 + RK_W - 1 of a block, joints i0 .. i1 - 1: the running poses (the 12 entries of their
   top rows) held in registers from joint to joint, read from P (or L_1 when i0 is 0) and written back
   to P at the end. Per joint, the operations and their order of fk.pxd's walk: T <- T Z(q) (a revolute
   joint: x' = c x + s y, y' = c y - s x on each row; a prismatic one: p += q z), frame and Jacobian
   columns out, then T <- T L_{i+1} (the operations of one row of linalg.tf_mul). */
RK_FK_STEPS_INLINE void RK_STEPS(const double* L, const unsigned char* rev, int n, int i0, int i1,
                           const double* qt, const double* st, const double* ct, double* P, double* F,
                           double* Z, Py_ssize_t ld, double* T, Py_ssize_t b0)
{
    const Py_ssize_t w = 16 * ((Py_ssize_t)n + 1);
    RK_T p0, p1, p2, p3, p4, p5, p6, p7, p8, p9, p10, p11;
    int i, k;
    /* frame f of lanes b0.. into F (m, n+1, 16): 4x4 row-major, last row 0 0 0 1 */
#define RK_FK_POSE(D, stride) \
    for (k = 0; k < RK_W; k++) { \
        double* T_ = (D) + (stride) * (b0 + k); \
        T_[0] = RK_LANE(p0, k); T_[1] = RK_LANE(p1, k); T_[2] = RK_LANE(p2, k); T_[3] = RK_LANE(p3, k); \
        T_[4] = RK_LANE(p4, k); T_[5] = RK_LANE(p5, k); T_[6] = RK_LANE(p6, k); T_[7] = RK_LANE(p7, k); \
        T_[8] = RK_LANE(p8, k); T_[9] = RK_LANE(p9, k); T_[10] = RK_LANE(p10, k); T_[11] = RK_LANE(p11, k); \
        T_[12] = 0.0; T_[13] = 0.0; T_[14] = 0.0; T_[15] = 1.0; \
    }
    if (i0 == 0) {
        p0 = RK_SPLAT(L[0]); p1 = RK_SPLAT(L[1]); p2 = RK_SPLAT(L[2]); p3 = RK_SPLAT(L[3]);
        p4 = RK_SPLAT(L[4]); p5 = RK_SPLAT(L[5]); p6 = RK_SPLAT(L[6]); p7 = RK_SPLAT(L[7]);
        p8 = RK_SPLAT(L[8]); p9 = RK_SPLAT(L[9]); p10 = RK_SPLAT(L[10]); p11 = RK_SPLAT(L[11]);
    } else {
        p0 = RK_LOAD(P + b0); p1 = RK_LOAD(P + RK_FK_BLOCK + b0);
        p2 = RK_LOAD(P + 2 * RK_FK_BLOCK + b0); p3 = RK_LOAD(P + 3 * RK_FK_BLOCK + b0);
        p4 = RK_LOAD(P + 4 * RK_FK_BLOCK + b0); p5 = RK_LOAD(P + 5 * RK_FK_BLOCK + b0);
        p6 = RK_LOAD(P + 6 * RK_FK_BLOCK + b0); p7 = RK_LOAD(P + 7 * RK_FK_BLOCK + b0);
        p8 = RK_LOAD(P + 8 * RK_FK_BLOCK + b0); p9 = RK_LOAD(P + 9 * RK_FK_BLOCK + b0);
        p10 = RK_LOAD(P + 10 * RK_FK_BLOCK + b0); p11 = RK_LOAD(P + 11 * RK_FK_BLOCK + b0);
    }
    for (i = i0; i < i1; i++) {
        /* L_{i+1}'s top rows in locals before any store (F and Z could alias L for all the compiler knows) */
        const double* A = L + 16 * (i + 1);
        const RK_T A0 = RK_SPLAT(A[0]), A1 = RK_SPLAT(A[1]), A2 = RK_SPLAT(A[2]), A3 = RK_SPLAT(A[3]);
        const RK_T A4 = RK_SPLAT(A[4]), A5 = RK_SPLAT(A[5]), A6 = RK_SPLAT(A[6]), A7 = RK_SPLAT(A[7]);
        const RK_T A8 = RK_SPLAT(A[8]), A9 = RK_SPLAT(A[9]), A10 = RK_SPLAT(A[10]), A11 = RK_SPLAT(A[11]);
        const Py_ssize_t j = (Py_ssize_t)RK_FK_BLOCK * (i - i0) + b0;
        RK_T a0, a1, a2, a3;
        if (rev[i]) {
            const RK_T c = RK_LOAD(ct + j), s = RK_LOAD(st + j);
            RK_T x;
            x = p0; p0 = (c * x) + (s * p1); p1 = (c * p1) - (s * x);
            x = p4; p4 = (c * x) + (s * p5); p5 = (c * p5) - (s * x);
            x = p8; p8 = (c * x) + (s * p9); p9 = (c * p9) - (s * x);
        } else {
            const RK_T q = RK_LOAD(qt + j);
            p3 = p3 + (q * p2);
            p7 = p7 + (q * p6);
            p11 = p11 + (q * p10);
        }
        if (F)
            RK_FK_POSE(F + 16 * (Py_ssize_t)i, w);
        if (Z) {
            /* joint i's origin p_i (column p) and axis z_i (column z) after its motion */
            RK_STORE(Z + ld * ((Py_ssize_t)n * 0 + i) + b0, p3);
            RK_STORE(Z + ld * ((Py_ssize_t)n * 1 + i) + b0, p7);
            RK_STORE(Z + ld * ((Py_ssize_t)n * 2 + i) + b0, p11);
            RK_STORE(Z + ld * ((Py_ssize_t)n * 3 + i) + b0, p2);
            RK_STORE(Z + ld * ((Py_ssize_t)n * 4 + i) + b0, p6);
            RK_STORE(Z + ld * ((Py_ssize_t)n * 5 + i) + b0, p10);
        }
        /* T <- T L_{i+1}, row by row */
        a0 = p0; a1 = p1; a2 = p2; a3 = p3;
        p0 = ((a0 * A0) + (a1 * A4)) + (a2 * A8);
        p1 = ((a0 * A1) + (a1 * A5)) + (a2 * A9);
        p2 = ((a0 * A2) + (a1 * A6)) + (a2 * A10);
        p3 = (((a0 * A3) + (a1 * A7)) + (a2 * A11)) + a3;
        a0 = p4; a1 = p5; a2 = p6; a3 = p7;
        p4 = ((a0 * A0) + (a1 * A4)) + (a2 * A8);
        p5 = ((a0 * A1) + (a1 * A5)) + (a2 * A9);
        p6 = ((a0 * A2) + (a1 * A6)) + (a2 * A10);
        p7 = (((a0 * A3) + (a1 * A7)) + (a2 * A11)) + a3;
        a0 = p8; a1 = p9; a2 = p10; a3 = p11;
        p8 = ((a0 * A0) + (a1 * A4)) + (a2 * A8);
        p9 = ((a0 * A1) + (a1 * A5)) + (a2 * A9);
        p10 = ((a0 * A2) + (a1 * A6)) + (a2 * A10);
        p11 = (((a0 * A3) + (a1 * A7)) + (a2 * A11)) + a3;
    }
    if (F && i1 == n)
        RK_FK_POSE(F + 16 * (Py_ssize_t)n, w);     /* the tool */
    if (T && i1 == n)
        RK_FK_POSE(T, 16);
    RK_STORE(P + b0, p0); RK_STORE(P + RK_FK_BLOCK + b0, p1);
    RK_STORE(P + 2 * RK_FK_BLOCK + b0, p2); RK_STORE(P + 3 * RK_FK_BLOCK + b0, p3);
    RK_STORE(P + 4 * RK_FK_BLOCK + b0, p4); RK_STORE(P + 5 * RK_FK_BLOCK + b0, p5);
    RK_STORE(P + 6 * RK_FK_BLOCK + b0, p6); RK_STORE(P + 7 * RK_FK_BLOCK + b0, p7);
    RK_STORE(P + 8 * RK_FK_BLOCK + b0, p8); RK_STORE(P + 9 * RK_FK_BLOCK + b0, p9);
    RK_STORE(P + 10 * RK_FK_BLOCK + b0, p10); RK_STORE(P + 11 * RK_FK_BLOCK + b0, p11);
}

#undef RK_FK_POSE
#undef RK_STEPS
#undef RK_T
#undef RK_W
#undef RK_LOAD
#undef RK_SPLAT
#undef RK_LANE
#undef RK_STORE
