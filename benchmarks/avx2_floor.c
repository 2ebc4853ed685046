/* The floor for bench_avx2.py: batch FK and geometric Jacobian of a serial chain written by hand with
 * AVX2 intrinsics, 4 configurations per vector, everything of a group of 4 in registers. Not part of
 * robkin: bench_avx2.py compiles it (cc -O3 -mavx2 -ffp-contract=off, no FMA, as robkin's kernels) into
 * a temporary folder and calls it through ctypes.
 *
 * The chain as robkin's compiled core holds it: T(q) = L_1 Z_1(q_1) ... L_n Z_n(q_n) L_{n+1}, L (n+1) x 16
 * row-major, rev[i] = 1 for a revolute joint (rotation about z), 0 for a prismatic one (along z). sin and
 * cos: Cody-Waite reduction by pi/2 in three parts and Taylor polynomials of the same degrees as robkin's
 * (sin to r^17, cos to r^18), without robkin's exact-reduction refinements. m must be a multiple of 4
 * (the benchmark's batches are).
 */
#include <immintrin.h>
#include <stdint.h>

static inline void sincos4(__m256d x, __m256d *s, __m256d *c)
{
    const __m256d shift = _mm256_set1_pd(0x1.8p52);
    __m256d t = _mm256_add_pd(_mm256_mul_pd(x, _mm256_set1_pd(0x1.45f306dc9c883p-1)), shift);
    __m256d k = _mm256_sub_pd(t, shift);
    __m256d r = _mm256_sub_pd(x, _mm256_mul_pd(k, _mm256_set1_pd(0x1.921fb544p+0)));
    r = _mm256_sub_pd(r, _mm256_mul_pd(k, _mm256_set1_pd(0x1.0b4611a6p-34)));
    r = _mm256_sub_pd(r, _mm256_mul_pd(k, _mm256_set1_pd(0x1.3198a2e037073p-69)));
    __m256d z = _mm256_mul_pd(r, r), z2 = _mm256_mul_pd(z, z), z4 = _mm256_mul_pd(z2, z2);
#define P2(a, b) _mm256_add_pd(_mm256_set1_pd(a), _mm256_mul_pd(z, _mm256_set1_pd(b)))
    __m256d ps = _mm256_add_pd(_mm256_add_pd(P2(-0x1.5555555555555p-3, 0x1.1111111111111p-7),
                     _mm256_mul_pd(z2, P2(-0x1.a01a01a01a01ap-13, 0x1.71de3a556c734p-19))),
                     _mm256_mul_pd(z4, _mm256_add_pd(P2(-0x1.ae64567f544e4p-26, 0x1.6124613a86d09p-33),
                     _mm256_mul_pd(z2, P2(-0x1.ae7f3e733b81fp-41, 0x1.952c77030ad4ap-49)))));
    ps = _mm256_add_pd(r, _mm256_mul_pd(r, _mm256_mul_pd(z, ps)));
    __m256d pc = _mm256_add_pd(_mm256_add_pd(P2(0x1.5555555555555p-5, -0x1.6c16c16c16c17p-10),
                     _mm256_mul_pd(z2, P2(0x1.a01a01a01a01ap-16, -0x1.27e4fb7789f5cp-22))),
                     _mm256_mul_pd(z4, _mm256_add_pd(P2(0x1.1eed8eff8d898p-29, -0x1.93974a8c07c9dp-37),
                     _mm256_mul_pd(z2, P2(0x1.ae7f3e733b81fp-45, -0x1.6827863b97d97p-53)))));
#undef P2
    pc = _mm256_add_pd(_mm256_sub_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(_mm256_set1_pd(0.5), z)),
                       _mm256_mul_pd(z2, pc));
    __m256i q = _mm256_castpd_si256(t);
    __m256i one = _mm256_set1_epi64x(1), two = _mm256_set1_epi64x(2);
    __m256d swap = _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(q, one), one));
    __m256d so = _mm256_blendv_pd(ps, pc, swap), co = _mm256_blendv_pd(pc, ps, swap);
    __m256i sneg = _mm256_slli_epi64(_mm256_and_si256(q, two), 62);
    __m256i cneg = _mm256_slli_epi64(_mm256_and_si256(_mm256_add_epi64(q, one), two), 62);
    *s = _mm256_xor_pd(so, _mm256_castsi256_pd(sneg));
    *c = _mm256_xor_pd(co, _mm256_castsi256_pd(cneg));
}

/* the 4 configurations' q_i, from Q (m x n row-major) */
static inline __m256d gather_q(const double *Q, int n, int i)
{
    return _mm256_set_pd(Q[3 * n + i], Q[2 * n + i], Q[n + i], Q[i]);
}

/* walk 4 configurations; P[12] = top rows of the tool poses; if Z, joint i's origin and axis after its
 * motion go to Z[6 * i + 0..2] (p) and Z[6 * i + 3..5] (z) */
static inline void walk4(const double *L, const unsigned char *rev, int n, const double *Q, __m256d P[12],
                         __m256d *Z)
{
    int e, i, r;
    for (e = 0; e < 12; e++)
        P[e] = _mm256_set1_pd(L[e]);
    for (i = 0; i < n; i++) {
        __m256d q = gather_q(Q, n, i);
        if (rev[i]) {
            __m256d s, c;
            sincos4(q, &s, &c);
            for (r = 0; r < 3; r++) {
                __m256d x = P[4 * r], y = P[4 * r + 1];
                P[4 * r] = _mm256_add_pd(_mm256_mul_pd(c, x), _mm256_mul_pd(s, y));
                P[4 * r + 1] = _mm256_sub_pd(_mm256_mul_pd(c, y), _mm256_mul_pd(s, x));
            }
        } else {
            for (r = 0; r < 3; r++)
                P[4 * r + 3] = _mm256_add_pd(P[4 * r + 3], _mm256_mul_pd(q, P[4 * r + 2]));
        }
        if (Z) {
            for (r = 0; r < 3; r++) {
                Z[6 * i + r] = P[4 * r + 3];
                Z[6 * i + 3 + r] = P[4 * r + 2];
            }
        }
        const double *A = L + 16 * (i + 1);
        __m256d A0 = _mm256_set1_pd(A[0]), A1 = _mm256_set1_pd(A[1]), A2 = _mm256_set1_pd(A[2]);
        __m256d A3 = _mm256_set1_pd(A[3]), A4 = _mm256_set1_pd(A[4]), A5 = _mm256_set1_pd(A[5]);
        __m256d A6 = _mm256_set1_pd(A[6]), A7 = _mm256_set1_pd(A[7]), A8 = _mm256_set1_pd(A[8]);
        __m256d A9 = _mm256_set1_pd(A[9]), A10 = _mm256_set1_pd(A[10]), A11 = _mm256_set1_pd(A[11]);
        for (r = 0; r < 3; r++) {
            __m256d a0 = P[4 * r], a1 = P[4 * r + 1], a2 = P[4 * r + 2], a3 = P[4 * r + 3];
            P[4 * r] = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a0, A0), _mm256_mul_pd(a1, A4)), _mm256_mul_pd(a2, A8));
            P[4 * r + 1] = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a0, A1), _mm256_mul_pd(a1, A5)), _mm256_mul_pd(a2, A9));
            P[4 * r + 2] = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a0, A2), _mm256_mul_pd(a1, A6)), _mm256_mul_pd(a2, A10));
            P[4 * r + 3] = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a0, A3), _mm256_mul_pd(a1, A7)),
                                                       _mm256_mul_pd(a2, A11)), a3);
        }
    }
}

/* T (m x 16): tool poses, 4x4 row-major */
void floor_fk(const double *L, const unsigned char *rev, int n, const double *Q, long m, double *T)
{
    long g;
    int e, b;
    __m256d P[12];
    double tmp[12][4] __attribute__((aligned(32)));
    for (g = 0; g < m; g += 4) {
        walk4(L, rev, n, Q + n * g, P, 0);
        for (e = 0; e < 12; e++)
            _mm256_store_pd(tmp[e], P[e]);
        for (b = 0; b < 4; b++) {
            double *Tb = T + 16 * (g + b);
            for (e = 0; e < 12; e++)
                Tb[e] = tmp[e][b];
            Tb[12] = 0.0; Tb[13] = 0.0; Tb[14] = 0.0; Tb[15] = 1.0;
        }
    }
}

/* J (m x 6 x n): geometric Jacobian [v; w] at the tool origin, in the base frame; n <= 64 */
void floor_jacobian(const double *L, const unsigned char *rev, int n, const double *Q, long m, double *J)
{
    long g;
    int i, r, b;
    __m256d P[12], Z[6 * 64];
    double col[6][4] __attribute__((aligned(32)));
    for (g = 0; g < m; g += 4) {
        walk4(L, rev, n, Q + n * g, P, Z);
        __m256d t0 = P[3], t1 = P[7], t2 = P[11];
        for (i = 0; i < n; i++) {
            __m256d z0 = Z[6 * i + 3], z1 = Z[6 * i + 4], z2 = Z[6 * i + 5];
            __m256d v0, v1, v2, w0, w1, w2;
            if (rev[i]) {
                __m256d d0 = _mm256_sub_pd(t0, Z[6 * i]), d1 = _mm256_sub_pd(t1, Z[6 * i + 1]);
                __m256d d2 = _mm256_sub_pd(t2, Z[6 * i + 2]);
                v0 = _mm256_sub_pd(_mm256_mul_pd(z1, d2), _mm256_mul_pd(z2, d1));
                v1 = _mm256_sub_pd(_mm256_mul_pd(z2, d0), _mm256_mul_pd(z0, d2));
                v2 = _mm256_sub_pd(_mm256_mul_pd(z0, d1), _mm256_mul_pd(z1, d0));
                w0 = z0; w1 = z1; w2 = z2;
            } else {
                v0 = z0; v1 = z1; v2 = z2;
                w0 = w1 = w2 = _mm256_setzero_pd();
            }
            _mm256_store_pd(col[0], v0); _mm256_store_pd(col[1], v1); _mm256_store_pd(col[2], v2);
            _mm256_store_pd(col[3], w0); _mm256_store_pd(col[4], w1); _mm256_store_pd(col[5], w2);
            for (b = 0; b < 4; b++) {
                double *Jb = J + 6 * n * (g + b) + i;
                for (r = 0; r < 6; r++)
                    Jb[n * r] = col[r][b];
            }
        }
    }
}
