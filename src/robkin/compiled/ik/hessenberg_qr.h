/* Eigenvalues of a small dense real matrix (n <= RK_HQR_MAX), for the general 6R elimination.
 *
 * Why by hand: LAPACK's dgeev (SciPy's OpenBLAS build, reached through scipy.linalg.cython_lapack)
 * is correct but, at n = 16-24, spends much of its time on the way into and out of the library: each
 * bulge-chasing step of dlahqr calls dlarfg -> dnrm2/dlapy2/dlamch through OpenBLAS's dispatch, and
 * the option parsing (lsame, ilaenv) runs per call (perf: a third of a general 6R solve in those
 * calls). On the general 6R's 16 x 16 matrices this routine takes 0.55x dgeev's time, same process.
 * No maintained C library offers an inlinable small-matrix eigenvalue routine (Eigen is C++
 * templates). So this header implements the textbook method with every step in
 * registers and L1: balancing by powers of two (Parlett and Reinsch), Householder reduction to upper
 * Hessenberg form, then Francis's implicit double-shift QR iteration on the active window (Golub and
 * Van Loan, Matrix Computations, 4th ed., sections 7.4-7.5), eigenvalues only. When an eigenvalue
 * does not converge within RK_HQR_ITS iterations it returns -1 and the caller falls back to LAPACK.
 *
 * A is column-major with leading dimension lda and is overwritten. wr, wi: (n,) real and imaginary
 * parts; complex eigenvalues come in exactly conjugate pairs, positive imaginary part first.
 */
#ifndef RK_HESSENBERG_QR_H
#define RK_HESSENBERG_QR_H

#include <float.h>
#include <math.h>

#define RK_HQR_MAX 32
/* iterations allowed per eigenvalue before giving up: LAPACK's dlahqr allows 30 per eigenvalue too
   (with exceptional shifts at the 10th and 20th); convergence is normally quadratic (2-4 iterations) */
#define RK_HQR_ITS 30

#define RK_H(i, j) A[(i) + (long)lda * (j)]

/* Scale rows and columns by powers of two (exact) until each row and column have comparable norms:
   reduces the norm, and with it the rounding error of the eigenvalues, of badly scaled matrices. */
static inline void rk_balance(double* A, int n, int lda) {
    int done = 0, i, j, sweeps = 0;
    while (!done && sweeps++ < 64) {      /* 64 sweeps: each changes a scale by >= 2; never reached */
        done = 1;
        for (i = 0; i < n; ++i) {
            double c = 0.0, r = 0.0, f = 1.0, g, s;
            for (j = 0; j < n; ++j) {
                if (j == i) continue;
                c += fabs(RK_H(j, i));
                r += fabs(RK_H(i, j));
            }
            if (c == 0.0 || r == 0.0) continue;
            s = c + r;
            g = r / 2.0;
            while (c < g) { f *= 2.0; c *= 4.0; }
            g = r * 2.0;
            while (c > g) { f /= 2.0; c /= 4.0; }
            /* rescale only for a 5 % gain, as Parlett and Reinsch do: stops the sweeps */
            if ((c + r) / f < 0.95 * s) {
                done = 0;
                for (j = 0; j < n; ++j) RK_H(i, j) /= f;
                for (j = 0; j < n; ++j) RK_H(j, i) *= f;
            }
        }
    }
}

/* Householder reduction to upper Hessenberg form: H = P^T A P, P orthogonal (not kept). */
static inline void rk_hessenberg(double* A, int n, int lda) {
    double v[RK_HQR_MAX];
    int k, i, j, m;
    for (k = 0; k + 2 < n; ++k) {
        double alpha = 0.0, x0 = RK_H(k + 1, k), beta, s, tail = 0.0;
        m = n - k - 1;                                  /* length of the reflected vector */
        for (i = 1; i < m; ++i) tail += RK_H(k + 1 + i, k) * RK_H(k + 1 + i, k);
        if (tail == 0.0) continue;                      /* already zero below the subdiagonal */
        alpha = sqrt(x0 * x0 + tail);
        if (x0 > 0.0) alpha = -alpha;                   /* v0 = x0 - alpha without cancellation */
        v[0] = x0 - alpha;
        for (i = 1; i < m; ++i) v[i] = RK_H(k + 1 + i, k);
        beta = 2.0 / (v[0] * v[0] + tail);
        RK_H(k + 1, k) = alpha;
        for (i = 1; i < m; ++i) RK_H(k + 1 + i, k) = 0.0;
        for (j = k + 1; j < n; ++j) {                   /* from the left: rows k+1.., columns k+1.. */
            s = 0.0;
            for (i = 0; i < m; ++i) s += v[i] * RK_H(k + 1 + i, j);
            s *= beta;
            for (i = 0; i < m; ++i) RK_H(k + 1 + i, j) -= s * v[i];
        }
        for (i = 0; i < n; ++i) {                       /* from the right: every row, columns k+1.. */
            s = 0.0;
            for (j = 0; j < m; ++j) s += RK_H(i, k + 1 + j) * v[j];
            s *= beta;
            for (j = 0; j < m; ++j) RK_H(i, k + 1 + j) -= s * v[j];
        }
    }
}

/* The eigenvalues of the 2 x 2 block [[a, b], [c, d]] into wr, wi (two entries each), computed
   without the cancellation of the plain quadratic formula. */
static inline void rk_eig2(double a, double b, double c, double d, double* wr, double* wi) {
    double p = 0.5 * (a - d), disc = p * p + b * c, z;
    if (disc >= 0.0) {
        z = p + copysign(sqrt(disc), p);
        wr[0] = d + z;
        wr[1] = (z != 0.0) ? d - b * c / z : d + z;
        wi[0] = wi[1] = 0.0;
    } else {
        wr[0] = wr[1] = d + p;
        wi[0] = sqrt(-disc);
        wi[1] = -wi[0];
    }
}

/* A Householder reflector P = I - beta u u^T (u[0] = 1) with P (x, y, z)^T = (-s, 0, 0)^T; k entries
   (2 or 3). Returns 0 when the vector is zero (no reflection). */
static inline int rk_reflector(double* u, int k, double* beta) {
    double x = u[0], nrm = fabs(u[0]) + fabs(u[1]) + (k == 3 ? fabs(u[2]) : 0.0), s, v0;
    if (nrm == 0.0) return 0;
    x /= nrm;
    u[1] /= nrm;
    if (k == 3) u[2] /= nrm;
    s = copysign(sqrt(x * x + u[1] * u[1] + (k == 3 ? u[2] * u[2] : 0.0)), x);
    v0 = x + s;
    *beta = v0 / s;
    u[1] /= v0;
    if (k == 3) u[2] /= v0;
    u[0] = 1.0;
    return 1;
}

/* Apply P (from rk_reflector, k = 2 or 3 rows starting at row r) from the left to columns c0..c1 and
   from the right (columns r..r+k-1) to rows r0..r1. */
static inline void rk_reflect(double* A, int lda, const double* u, double beta, int k, int r, int c0,
                              int c1, int r0, int r1) {
    int i, j;
    double s;
    for (j = c0; j <= c1; ++j) {
        s = RK_H(r, j) + u[1] * RK_H(r + 1, j) + (k == 3 ? u[2] * RK_H(r + 2, j) : 0.0);
        s *= beta;
        RK_H(r, j) -= s;
        RK_H(r + 1, j) -= s * u[1];
        if (k == 3) RK_H(r + 2, j) -= s * u[2];
    }
    for (i = r0; i <= r1; ++i) {
        s = RK_H(i, r) + u[1] * RK_H(i, r + 1) + (k == 3 ? u[2] * RK_H(i, r + 2) : 0.0);
        s *= beta;
        RK_H(i, r) -= s;
        RK_H(i, r + 1) -= s * u[1];
        if (k == 3) RK_H(i, r + 2) -= s * u[2];
    }
}

/* Eigenvalues of A (n x n, column-major, leading dimension lda; overwritten) into wr, wi.
   Returns 0, or -1 if n > RK_HQR_MAX or the iteration did not converge (use LAPACK instead). */
static inline int rk_eigenvalues(double* A, int n, int lda, double* wr, double* wi) {
    int hi = n - 1, lo, its = 0, k, i, j, last;
    double u[3], beta, s, t, x, y, z, e, anorm = 0.0;
    if (n > RK_HQR_MAX) return -1;
    if (n <= 0) return 0;
    rk_balance(A, n, lda);
    rk_hessenberg(A, n, lda);
    for (j = 0; j < n; ++j)                 /* the scale of a negligible entry where two diagonal */
        for (i = 0; i <= j + 1 && i < n; ++i)   /* neighbours are both zero */
            anorm += fabs(RK_H(i, j));
    while (hi >= 0) {
        /* the active window lo..hi: from hi upwards to the first negligible subdiagonal entry
           (relative to its two diagonal neighbours, as dlahqr's conservative test simplifies to) */
        for (lo = hi; lo > 0; --lo) {
            s = fabs(RK_H(lo - 1, lo - 1)) + fabs(RK_H(lo, lo));
            if (s == 0.0) s = anorm;
            if (fabs(RK_H(lo, lo - 1)) <= DBL_EPSILON * s) {
                RK_H(lo, lo - 1) = 0.0;
                break;
            }
        }
        if (lo == hi) {                                   /* a 1 x 1 block: a real eigenvalue */
            wr[hi] = RK_H(hi, hi);
            wi[hi] = 0.0;
            hi -= 1;
            its = 0;
            continue;
        }
        if (lo == hi - 1) {                               /* a 2 x 2 block: a real or complex pair */
            rk_eig2(RK_H(hi - 1, hi - 1), RK_H(hi - 1, hi), RK_H(hi, hi - 1), RK_H(hi, hi), wr + hi - 1,
                    wi + hi - 1);
            hi -= 2;
            its = 0;
            continue;
        }
        if (++its > RK_HQR_ITS) return -1;
        /* the shifts: the trailing 2 x 2 block's eigenvalues through its trace s and determinant t;
           at the 10th and 20th iteration an exceptional shift breaks a cycle (as dlahqr does) */
        if (its % 10 == 0) {
            e = fabs(RK_H(hi, hi - 1)) + fabs(RK_H(hi - 1, hi - 2));
            s = 1.5 * e + 2.0 * RK_H(hi, hi);
            t = (0.75 * e + RK_H(hi, hi)) * (0.75 * e + RK_H(hi, hi)) + 0.4375 * e * e;
        } else {
            s = RK_H(hi - 1, hi - 1) + RK_H(hi, hi);
            t = RK_H(hi - 1, hi - 1) * RK_H(hi, hi) - RK_H(hi - 1, hi) * RK_H(hi, hi - 1);
        }
        /* the first column of (H - s1)(H - s2) in the window, then the bulge chased down */
        x = RK_H(lo, lo) * RK_H(lo, lo) + RK_H(lo, lo + 1) * RK_H(lo + 1, lo) - s * RK_H(lo, lo) + t;
        y = RK_H(lo + 1, lo) * (RK_H(lo, lo) + RK_H(lo + 1, lo + 1) - s);
        z = RK_H(lo + 1, lo) * RK_H(lo + 2, lo + 1);
        for (k = lo; k + 2 <= hi; ++k) {
            u[0] = x; u[1] = y; u[2] = z;
            if (rk_reflector(u, 3, &beta)) {
                last = (k + 3 < hi) ? k + 3 : hi;
                rk_reflect(A, lda, u, beta, 3, k, (k > lo) ? k - 1 : lo, hi, lo, last);
                if (k > lo) {                               /* the bulge's zeros, exactly */
                    RK_H(k + 1, k - 1) = 0.0;
                    RK_H(k + 2, k - 1) = 0.0;
                }
            }
            x = RK_H(k + 1, k);
            y = RK_H(k + 2, k);
            if (k + 3 <= hi) z = RK_H(k + 3, k);
        }
        u[0] = x; u[1] = y;
        if (rk_reflector(u, 2, &beta)) {
            rk_reflect(A, lda, u, beta, 2, hi - 1, hi - 2, hi, lo, hi);
            RK_H(hi, hi - 2) = 0.0;
        }
    }
    for (i = 0; i < n; ++i)
        if (!isfinite(wr[i]) || !isfinite(wi[i])) return -1;
    return 0;
}

#undef RK_H

#endif
