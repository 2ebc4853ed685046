# cython: language_level=3
"""The small pieces of the general 6R elimination (``closed_form_general6r``) as ``cdef inline``
functions: rotations about z, lines moved by transforms, Raghavan and Roth's 14 quantities of a line,
the null vector of a singular matrix, half-angle ratios, and the 3 x 3 x 3 coefficient transform."""

from libc.math cimport atan2, cos, fabs, sin, sqrt
from robkin.compiled.runtime.linalg cimport cross3, dot3
from scipy.linalg.cython_lapack cimport dgeev, dggev


cdef extern from "ik/hessenberg_qr.h" nogil:
    int rk_eigenvalues(double* A, int n, int lda, double* wr, double* wi)


cdef inline int small_eigenvalues(double* A, int n, int lda, double* scratch, double* wr, double* wi,
                                  double* lw, int lwork) noexcept nogil:
    """The eigenvalues of A (n x n, column-major, leading dimension lda) into wr, wi: by
    ``hessenberg_qr.h`` on a copy in scratch (n * n doubles), or by LAPACK ``dgeev`` on A where that
    does not converge (lw: lwork doubles of LAPACK workspace). Returns LAPACK's info (0 from the
    header)."""
    cdef int i, j, info = 0, ldv = 1
    cdef char jobN = b'N'
    for j in range(n):
        for i in range(n):
            scratch[i + n * j] = A[i + lda * j]
    if rk_eigenvalues(scratch, n, n, wr, wi) == 0:
        return 0
    dgeev(&jobN, &jobN, &n, A, &lda, wr, wi, NULL, &ldv, NULL, &ldv, lw, &lwork, &info)
    return info


cdef inline void reflect(const double* Vq, const double* tau, int c, double* col, int stride) noexcept nogil:
    """Householder reflector c of ``eliminate_block`` (vector Vq[14 c ..], factor tau[c]) applied to the
    14 entries col[stride * r]."""
    cdef double dotv = 0.0
    cdef int r
    for r in range(c, 14):
        dotv += Vq[14 * c + r] * col[stride * r]
    dotv *= tau[c]
    for r in range(c, 14):
        col[stride * r] -= dotv * Vq[14 * c + r]


cdef inline bint eliminate_block(double* Rc, double* Px, double* Vq, double* tau, double rank_tol) noexcept nogil:
    """Householder QR of the 14 x 8 block C8 = Rc[:, 1:] (Rc: 14 x 9 row-major; R left in its place),
    Q^T applied to Px (14 x 27 row-major): the 8 eliminated unknowns leave Px's rows 8..13 free of
    them. Vq (14 x 8, by column) and tau (8) keep the reflectors. False when a column's remaining norm
    is below rank_tol x the first column's (the block is rank-deficient: nothing is eliminated)."""
    cdef double nrm, x, alpha, big = 0.0
    cdef int c, r, k
    for c in range(8):
        nrm = 0.0
        for r in range(c, 14):
            x = Rc[9 * r + 1 + c]
            nrm += x * x
        nrm = sqrt(nrm)
        if c == 0:
            big = nrm
        if nrm <= rank_tol * big or nrm == 0.0:
            return False
        alpha = -nrm if Rc[9 * c + 1 + c] >= 0.0 else nrm
        for r in range(14):
            Vq[14 * c + r] = 0.0 if r < c else Rc[9 * r + 1 + c]
        Vq[14 * c + c] -= alpha
        nrm = 0.0
        for r in range(c, 14):
            nrm += Vq[14 * c + r] * Vq[14 * c + r]
        tau[c] = 2.0 / nrm
        for k in range(c, 8):                  # the block's remaining columns
            reflect(Vq, tau, c, Rc + 1 + k, 9)
        for k in range(27):                    # Px's columns
            reflect(Vq, tau, c, Px + k, 27)
    return True


cdef inline void solve_block(const double* Rc, const double* Vq, const double* tau, double* y, double* m8) noexcept nogil:
    """The least-squares m8 (8) of C8 m8 = y (14, overwritten with Q^T y) by ``eliminate_block``'s QR."""
    cdef int c, i, k
    cdef double x
    for c in range(8):
        reflect(Vq, tau, c, y, 1)
    for i in range(7, -1, -1):
        x = y[i]
        for k in range(i + 1, 8):
            x -= Rc[9 * i + 1 + k] * m8[k]
        m8[i] = x / Rc[9 * i + 1 + i]


cdef inline void rz_mul(double t, const double* A, double* out) noexcept nogil:
    """out = Rz(t) A for 4x4 row-major transforms."""
    cdef double c = cos(t), s = sin(t)
    cdef int j
    for j in range(4):
        out[j] = c * A[j] - s * A[4 + j]
        out[4 + j] = s * A[j] + c * A[4 + j]
        out[8 + j] = A[8 + j]
        out[12 + j] = A[12 + j]


cdef inline void move_line(const double* A, const double* p, const double* l, double* po, double* lo) noexcept nogil:
    """The line (point p, direction l) moved by the 4x4 transform A."""
    cdef int i
    for i in range(3):
        lo[i] = A[4 * i] * l[0] + A[4 * i + 1] * l[1] + A[4 * i + 2] * l[2]
        po[i] = A[4 * i] * p[0] + A[4 * i + 1] * p[1] + A[4 * i + 2] * p[2] + A[4 * i + 3]


cdef inline void line_quantities(const double* p, const double* l, double* out, int stride) noexcept nogil:
    """Raghavan and Roth's 14 quantities of the line (p, l): p, l, p.p, p.l, p x l, (p.p) l - 2 (p.l) p;
    out[stride * k] for k < 14."""
    cdef double pp = dot3(p, p), pl = dot3(p, l)
    cdef double x[3]
    cdef int i
    cross3(p, l, x)
    for i in range(3):
        out[stride * i] = p[i]
        out[stride * (3 + i)] = l[i]
        out[stride * (8 + i)] = x[i]
        out[stride * (11 + i)] = pp * l[i] - 2.0 * pl * p[i]
    out[stride * 6] = pp
    out[stride * 7] = pl


cdef inline void null_vector(double* A, int n, double* v, int* cp) noexcept nogil:
    """v (n,) spanning the (numerical) null space of the singular A (n x n row-major, overwritten):
    LU with full pivoting, the last pivot taken as zero, back-substitution. Rows and columns are
    swapped in place (cp records the columns' order), so the inner loops run over contiguous memory:
    the same pivots and operations as index arrays would give, without their indirection."""
    cdef int i, j, k, bi, bj, t
    cdef double big, x, f, p
    cdef double* rk
    cdef double* ri
    for i in range(n):
        cp[i] = i
    for k in range(n - 1):
        big = -1.0
        bi = k
        bj = k
        for i in range(k, n):
            ri = A + i * n
            for j in range(k, n):
                x = fabs(ri[j])
                if x > big:
                    big, bi, bj = x, i, j
        if bi != k:
            for j in range(n):
                x = A[k * n + j]; A[k * n + j] = A[bi * n + j]; A[bi * n + j] = x
        if bj != k:
            for i in range(n):
                x = A[i * n + k]; A[i * n + k] = A[i * n + bj]; A[i * n + bj] = x
            t = cp[k]; cp[k] = cp[bj]; cp[bj] = t
        if big == 0.0:
            continue
        rk = A + k * n
        p = rk[k]
        for i in range(k + 1, n):
            ri = A + i * n
            f = ri[k] / p
            ri[k] = f
            for j in range(k + 1, n):
                ri[j] -= f * rk[j]
    v[cp[n - 1]] = 1.0
    for i in range(n - 2, -1, -1):
        x = 0.0
        for j in range(i + 1, n):
            x += A[i * n + j] * v[cp[j]]
        f = A[i * n + i]
        v[cp[i]] = -x / f if f != 0.0 else 0.0


cdef inline double pair_angle(const double* v, int stride_lo, int count_i, int count_j, int si, int sj) noexcept nogil:
    """The angle theta' with (lo, up) ~ (cos theta'/2, sin theta'/2) over the monomial pairs of the
    null vector v: lo = v[si * i + sj * j], up = the entry stride_lo further (the next power)."""
    cdef double a = 0.0, b = 0.0, c = 0.0, lo, up
    cdef int i, j
    for i in range(count_i):
        for j in range(count_j):
            lo = v[si * i + sj * j]
            up = v[si * i + sj * j + stride_lo]
            a += lo * lo
            b += up * up
            c += lo * up
    return atan2(2.0 * c, a - b)


cdef inline void transform3(const double* f, const double* W, double* out) noexcept nogil:
    """out[9 I + 3 J + K] = sum W[I, i] W[J, j] W[K, k] f[9 i + 3 j + k] (3 x 3 x 3 tensor, each axis by W)."""
    cdef double t1[27]
    cdef double t2[27]
    cdef int I, i, j, k
    cdef double x
    for I in range(3):              # axis c
        for i in range(3):
            for j in range(3):
                x = 0.0
                for k in range(3):
                    x += W[3 * I + k] * f[9 * i + 3 * j + k]
                t1[9 * i + 3 * j + I] = x
    for I in range(3):              # axis b
        for i in range(3):
            for k in range(3):
                x = 0.0
                for j in range(3):
                    x += W[3 * I + j] * t1[9 * i + 3 * j + k]
                t2[9 * i + 3 * I + k] = x
    for I in range(3):              # axis a
        for j in range(3):
            for k in range(3):
                x = 0.0
                for i in range(3):
                    x += W[3 * I + i] * t2[9 * i + 3 * j + k]
                out[9 * I + 3 * j + k] = x


cdef inline int quadratic_pencil_eigenvalues(const double* M0, const double* M1, const double* M2, int m,
                                             double* Ap, double* Bp, double* ar, double* ai, double* be,
                                             double* lw, int lwork, double* col, int* piv,
                                             double rcond, const double* Q2, int nd) noexcept nogil:
    """The 2m eigenvalues x = (ar + i ai) / be of det(M0 + M1 x + M2 x^2) = 0 (m x m row-major blocks).

    M2 is LU-factored (partial pivoting); if its pivots stay above ``rcond`` x the largest, the
    companion matrix [[0, I], [-M2^-1 M0, -M2^-1 M1]] goes to ``small_eigenvalues`` (be = 1), else the
    pencil [[0, I], [-M0, -M1]] - x [[I, 0], [0, M2]] to ``dggev`` (infinite eigenvalues: be = 0). Ap,
    Bp: (2m)^2 doubles of scratch each; lw: lwork doubles; col: m doubles; piv: m ints. Returns LAPACK's
    info.

    Q2 (2m x nd, column-major, orthonormal columns) or NULL: the complement of an invariant subspace of
    the companion matrix C whose eigenvalues are known (the general 6R's spurious roots): the header then
    solves Q2^T C Q2 (nd x nd), whose eigenvalues are C's others (Q = [Q1 Q2] makes Q^T C Q block upper
    triangular), and be = 0 marks the 2m - nd entries left out. The pencil path ignores Q2.
    """
    cdef int n2 = 2 * m, lda = 2 * m, ldv = 1, info = 0, i, j, k, c
    cdef double big, x, piv_min = 1e308, piv_max = 0.0
    cdef char jobN = b'N'
    for i in range(m * m):
        Bp[i] = M2[i]
    for k in range(m):
        big = -1.0
        j = k
        for i in range(k, m):
            if fabs(Bp[m * i + k]) > big:
                big = fabs(Bp[m * i + k])
                j = i
        piv[k] = j
        if j != k:
            for i in range(m):
                x = Bp[m * k + i]
                Bp[m * k + i] = Bp[m * j + i]
                Bp[m * j + i] = x
        piv_min = min(piv_min, big)
        piv_max = max(piv_max, big)
        if big == 0.0:
            break
        for i in range(k + 1, m):
            x = Bp[m * i + k] / Bp[m * k + k]
            Bp[m * i + k] = x
            for j in range(k + 1, m):
                Bp[m * i + j] -= x * Bp[m * k + j]
    for i in range(n2 * n2):
        Ap[i] = 0.0
    for i in range(m):
        Ap[i + n2 * (m + i)] = 1.0
    if piv_max > 0.0 and piv_min > rcond * piv_max:
        for c in range(n2):                    # column c of -M2^-1 [M0 M1]: row swaps, L, then U
            for i in range(m):
                col[i] = -(M0[m * i + c] if c < m else M1[m * i + c - m])
            for k in range(m):
                j = piv[k]
                if j != k:
                    x = col[k]
                    col[k] = col[j]
                    col[j] = x
            for i in range(m):
                for k in range(i):
                    col[i] -= Bp[m * i + k] * col[k]
            for i in range(m - 1, -1, -1):
                for k in range(i + 1, m):
                    col[i] -= Bp[m * i + k] * col[k]
                col[i] /= Bp[m * i + i]
            for i in range(m):
                Ap[m + i + n2 * c] = col[i]
        if Q2 != NULL:
            # Y = C Q2 into Bp (C = [[0, I], [X0, X1]]: Y's top rows are Q2's bottom rows), then
            # Q2^T Y into Ap (nd x nd, leading dimension nd)
            for j in range(nd):
                for i in range(m):
                    Bp[i + n2 * j] = Q2[m + i + n2 * j]
                    x = 0.0
                    for k in range(n2):
                        x += Ap[m + i + n2 * k] * Q2[k + n2 * j]
                    Bp[m + i + n2 * j] = x
            for j in range(nd):
                for i in range(nd):
                    x = 0.0
                    for k in range(n2):
                        x += Q2[k + n2 * i] * Bp[k + n2 * j]
                    Ap[i + nd * j] = x
            info = small_eigenvalues(Ap, nd, nd, Bp, ar, ai, lw, lwork)
            for i in range(n2):
                be[i] = 1.0 if i < nd else 0.0
            return info
        info = small_eigenvalues(Ap, n2, lda, Bp, ar, ai, lw, lwork)
        for i in range(n2):
            be[i] = 1.0
        return info
    for i in range(n2 * n2):
        Bp[i] = 0.0
    for i in range(m):
        Bp[i + n2 * i] = 1.0
        for j in range(m):
            Ap[m + i + n2 * j] = -M0[m * i + j]
            Ap[m + i + n2 * (m + j)] = -M1[m * i + j]
            Bp[m + i + n2 * (m + j)] = M2[m * i + j]
    dggev(&jobN, &jobN, &n2, Ap, &lda, Bp, &lda, ar, ai, be, NULL, &ldv, NULL, &ldv, lw, &lwork, &info)
    return info
