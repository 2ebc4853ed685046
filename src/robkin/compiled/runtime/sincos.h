/* sin and cos together, written so that a loop over an array of angles auto-vectorises.
 *
 * The compiled kinematics kernels call sin and cos of every revolute joint's value; libm's calls are
 * scalar (~15-20 ns each), which was most of a batch FK. Here one branch-free computation serves every
 * lane, and the single-configuration paths run the very same code, so single and batch results are equal
 * bit for bit. Build with -ffp-contract=off (setup.py): a fused multiply-add in one path and not in the
 * other would break that equality.
 *
 * Method, for |x| <= RK_SINCOS_BOUND:
 *   1. k = x * 2/pi rounded to the nearest integer (adding and subtracting 1.5 * 2^52 rounds a double of
 *      magnitude < 2^51 to an integer in the current rounding mode, round-to-nearest by default), and the
 *      quadrant k mod 4 read from the low bits of that sum.
 *   2. Cody-Waite reduction r = x - k pi/2 with pi/2 split into four parts: three of 33 significant bits
 *      and a 53-bit tail (pi/2 to ~152 bits). For |k| < 2^20 every product k * part of a 33-bit part is
 *      exact, and x - k * RK_PIO2_1 is exact by Sterbenz's lemma, so r keeps its full relative accuracy
 *      even for x next to a multiple of pi/2 (where r is ~1e-17 and the answer is r itself). The rounding
 *      error of the second subtraction is recovered exactly and added back with the small parts, so r is
 *      rounded once (r rounded at every step cost up to 2 ulp in the results for |x| ~ 1e3-1e5).
 *   3. Taylor polynomials of sin and cos on |r| <= pi/4 (a rounding of k can give |r| a hair above pi/4):
 *      sin to r^17, cos to r^18. The first omitted terms, r^19/19! and r^20/20! at r = pi/4, are below
 *      2e-19, i.e. < 0.002 ulp of the results there. cos is summed as w + ((1 - w) - r^2/2 + ...) with
 *      w = 1 - r^2/2, which carries the rounding error of the dominant subtraction along.
 *   4. Quadrant selection with bit masks (swap sin and cos for odd k, flip signs), no branches.
 * Outside the bound (and for inf/nan, which the kernels' callers reject anyway) libm's sin and cos are
 * used. Measured error against glibc over > 1.2e6 arguments (tests/test_batch_kernels.py): at most
 * 1 ulp. (One difference from libm: sin(-0.0) is +0.0.)
 */
#ifndef ROBKIN_SINCOS_H
#define ROBKIN_SINCOS_H

#include <math.h>
#include <stdint.h>
#include <string.h>

/* 1e5 rad (~16 000 turns): |k| <= 63 662 < 2^16, far inside the 2^20 the exact products need; within 1
 * ulp of glibc all the way (tests/test_batch_kernels.py). Larger arguments go to libm. */
#define RK_SINCOS_BOUND 1.0e5

#define RK_TWO_OVER_PI 0x1.45f306dc9c883p-1
#define RK_ROUND_SHIFT 0x1.8p52
#define RK_PIO2_1 0x1.921fb544p+0
#define RK_PIO2_2 0x1.0b4611a6p-34
#define RK_PIO2_3 0x1.3198a2ep-69
#define RK_PIO2_4 0x1.b839a252049c1p-104

/* sin(r) and cos(r) for |r| <= pi/4 (a little beyond is fine), then placed in quadrant k mod 4. */
static inline void rk_sincos_core(double x, double *s, double *c)
{
    double t = x * RK_TWO_OVER_PI + RK_ROUND_SHIFT;
    double k = t - RK_ROUND_SHIFT;
    double r1 = x - k * RK_PIO2_1;                        /* exact */
    double kp2 = k * RK_PIO2_2;                           /* exact */
    double r2 = r1 - kp2;
    double tail = (((r1 - r2) - kp2) - k * RK_PIO2_3) - k * RK_PIO2_4;   /* (r1 - r2) - kp2: r2's rounding error */
    double r = r2 + tail;                                 /* the one rounding of r that matters */
    double z = r * r;
    double z2 = z * z;
    double z4 = z2 * z2;
    /* 1/3!, 1/5!, ..., 1/17! and 1/4!, ..., 1/18!, each the double nearest the exact reciprocal, summed
     * in Estrin's order (pairs, then pairs of pairs): a short dependency chain, for the one-angle calls */
    double ps = r + r * (z * ((-0x1.5555555555555p-3 + z * 0x1.1111111111111p-7)
              + z2 * (-0x1.a01a01a01a01ap-13 + z * 0x1.71de3a556c734p-19)
              + z4 * ((-0x1.ae64567f544e4p-26 + z * 0x1.6124613a86d09p-33)
              + z2 * (-0x1.ae7f3e733b81fp-41 + z * 0x1.952c77030ad4ap-49))));
    double hz = 0.5 * z;
    double w = 1.0 - hz;
    double pc = w + (((1.0 - w) - hz) + z2 * ((0x1.5555555555555p-5 + z * -0x1.6c16c16c16c17p-10)
              + z2 * (0x1.a01a01a01a01ap-16 + z * -0x1.27e4fb7789f5cp-22)
              + z4 * ((0x1.1eed8eff8d898p-29 + z * -0x1.93974a8c07c9dp-37)
              + z2 * (0x1.ae7f3e733b81fp-45 + z * -0x1.6827863b97d97p-53))));
    uint64_t q, sb, cb, swap, so, co;
    memcpy(&q, &t, sizeof q);        /* low bits of t's significand: k in two's complement */
    memcpy(&sb, &ps, sizeof sb);
    memcpy(&cb, &pc, sizeof cb);
    swap = (uint64_t)0 - (q & 1);    /* all ones for odd k: sin and cos trade places */
    so = (sb & ~swap) | (cb & swap);
    co = (cb & ~swap) | (sb & swap);
    so ^= (q & 2) << 62;             /* sin is negative in quadrants 2, 3 */
    co ^= ((q + 1) & 2) << 62;       /* cos in quadrants 1, 2 */
    memcpy(s, &so, sizeof so);
    memcpy(c, &co, sizeof co);
}

/* *s, *c = sin(x), cos(x) for one angle: the same computation inline (one configuration's walk calls this,
 * a block's calls rk_sincos_array; both give the same bits). */
static inline void rk_sincos_one(double x, double *s, double *c)
{
    if (fabs(x) <= RK_SINCOS_BOUND) {
        rk_sincos_core(x, s, c);
    } else {
        *s = sin(x);
        *c = cos(x);
    }
}

/* With GCC on x86-64 Linux with glibc (which provides ifuncs) the array version is compiled twice, for AVX2 (4 doubles a vector) and for the
 * baseline (SSE2, 2 doubles), and the loader picks the one the CPU runs (an ifunc, resolved once). Both
 * do the same IEEE operations in the same order (AVX2 brings no FMA, and -ffp-contract=off forbids it
 * anyway), so results do not depend on the clone. Elsewhere: the baseline only. A module already built
 * for AVX2 (kernels_avx2, see kernels.pyx) needs no clones and inlines the one version. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && defined(__GLIBC__) \
    && !defined(__AVX2__)
#define RK_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define RK_SIMD_CLONES
#endif

/* s[b], c[b] = sin(x[b]), cos(x[b]) for b < m; the first loop vectorises and also notes, branch-free,
 * whether any argument lies outside the reduction's range (or is not finite); only then does the second
 * loop patch those with libm. That loop, a compare and a branch per argument, had run on every call:
 * ~10 ns of a 7-joint configuration's batch FK (59 -> 49 ns with AVX2 in a C harness, N = 1e5). */
RK_SIMD_CLONES static void rk_sincos_array(const double *x, double *s, double *c, int m)
{
    int b, far = 0;
    for (b = 0; b < m; b++) {
        rk_sincos_core(x[b], s + b, c + b);
        far |= !(fabs(x[b]) <= RK_SINCOS_BOUND);
    }
    if (far)
        for (b = 0; b < m; b++)
            if (!(fabs(x[b]) <= RK_SINCOS_BOUND)) {
                s[b] = sin(x[b]);
                c[b] = cos(x[b]);
            }
}

#endif
