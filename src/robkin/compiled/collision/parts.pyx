# cython: language_level=3
"""The convex parts of two links: is a plane between them? (``parts_apart``, GJK on the parts' points.)

Between the capsules (``capsules.pyx``) and the exact mesh check: each link is a few convex parts
(their points, the hull vertices, in their frames at q = 0), and a pair of links is cleared at a
configuration when every part of one is apart from every part of the other: capsules around them
apart, or a separating plane found by GJK on the Minkowski difference. A plane is proof (the support
values themselves show it), so the answer "apart" is never wrong; anything the search does not prove
(touching, overlapping, a degenerate step, too many steps) is "not proven", for the exact check.
Queries are split over threads (``prange``; ``threads`` 0: automatic, ``robkin.threads``).
"""

cimport numpy as cnp
from cython.parallel cimport prange
from libc.stdlib cimport malloc, free
from robkin.compiled.collision.segments cimport segment_distance2
from robkin.compiled.runtime.threads cimport batch_threads

import numpy as np

cnp.import_array()

cdef enum:
    # GJK steps before giving up (and answering "not proven apart", which the caller checks exactly)
    GJK_STEPS = 64


cdef inline double dot3(const double* a, const double* b) noexcept nogil:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


cdef inline void cross3(const double* a, const double* b, double* out) noexcept nogil:
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


cdef inline void triple(const double* a, const double* b, const double* c, double* out) noexcept nogil:
    """(a x b) x c."""
    cdef double t[3]
    cross3(a, b, t)
    cross3(t, c, out)


cdef double support_gap(const double* A, int na, const double* B, int nb, const double* d, double* w) noexcept nogil:
    """w = the point of A - B farthest along d (A's farthest minus B's nearest); returns d . w."""
    cdef int i, ia = 0, ib = 0
    cdef double best = -1e300, low = 1e300, x
    for i in range(na):
        x = dot3(A + 3 * i, d)
        if x > best:
            best = x
            ia = i
    for i in range(nb):
        x = dot3(B + 3 * i, d)
        if x < low:
            low = x
            ib = i
    for i in range(3):
        w[i] = A[3 * ia + i] - B[3 * ib + i]
    return best - low


cdef bint apart(const double* A, int na, const double* B, int nb, const double* start) noexcept nogil:
    """True only when a plane separates the convex hulls of the points A and B (both (k, 3), one frame):
    a direction d with max over A of d.a < min over B of d.b, found by GJK on A - B. Anything else
    (touching, overlapping, a degenerate step, too many steps) is False: "not proven apart". ``start``:
    the first search direction (B's centre to A's: most pairs are proven apart at the first step)."""
    cdef double S[12]      # the simplex, newest point first
    cdef double d[3]
    cdef double w[3]
    cdef double ao[3]
    cdef double ab[3]
    cdef double ac[3]
    cdef double ad[3]
    cdef double abc[3]
    cdef double acd[3]
    cdef double adb[3]
    cdef double t[3]
    cdef int m = 0, step, i
    cdef double n2
    for i in range(3):
        d[i] = start[i]
    if dot3(d, d) < 1e-300:
        d[0] = 1.0
    for step in range(GJK_STEPS):
        if support_gap(A, na, B, nb, d, w) < 0.0:
            return True                    # A's farthest along d is short of B's nearest: apart
        # the new point first
        for i in range(3 * m - 1, -1, -1):
            S[i + 3] = S[i]
        for i in range(3):
            S[i] = w[i]
            ao[i] = -w[i]
        m += 1
        if m == 1:
            for i in range(3):
                d[i] = ao[i]
        elif m == 2:
            for i in range(3):
                ab[i] = S[3 + i] - S[i]
            if dot3(ab, ao) > 0.0:
                triple(ab, ao, ab, d)
            else:
                m = 1
                for i in range(3):
                    d[i] = ao[i]
        elif m == 3:
            for i in range(3):
                ab[i] = S[3 + i] - S[i]
                ac[i] = S[6 + i] - S[i]
            cross3(ab, ac, abc)
            cross3(abc, ac, t)
            if dot3(t, ao) > 0.0:
                if dot3(ac, ao) > 0.0:     # edge a-c
                    for i in range(3):
                        S[3 + i] = S[6 + i]
                    m = 2
                    triple(ac, ao, ac, d)
                elif dot3(ab, ao) > 0.0:   # edge a-b
                    m = 2
                    triple(ab, ao, ab, d)
                else:
                    m = 1
                    for i in range(3):
                        d[i] = ao[i]
            else:
                cross3(ab, abc, t)
                if dot3(t, ao) > 0.0:
                    if dot3(ab, ao) > 0.0:
                        m = 2
                        triple(ab, ao, ab, d)
                    else:
                        m = 1
                        for i in range(3):
                            d[i] = ao[i]
                elif dot3(abc, ao) > 0.0:
                    for i in range(3):
                        d[i] = abc[i]
                else:                      # below the triangle: wind it the other way
                    for i in range(3):
                        t[i] = S[3 + i]
                        S[3 + i] = S[6 + i]
                        S[6 + i] = t[i]
                        d[i] = -abc[i]
        else:
            for i in range(3):
                ab[i] = S[3 + i] - S[i]
                ac[i] = S[6 + i] - S[i]
                ad[i] = S[9 + i] - S[i]
            cross3(ab, ac, abc)
            cross3(ac, ad, acd)
            cross3(ad, ab, adb)
            if dot3(abc, ao) > 0.0:        # beyond face a-b-c: keep it
                m = 3
                for i in range(3):
                    d[i] = abc[i]
            elif dot3(acd, ao) > 0.0:      # face a-c-d
                m = 3
                for i in range(3):
                    S[3 + i] = S[6 + i]
                    S[6 + i] = S[9 + i]
                    d[i] = acd[i]
            elif dot3(adb, ao) > 0.0:      # face a-d-b
                m = 3
                for i in range(3):
                    S[6 + i] = S[3 + i]
                    S[3 + i] = S[9 + i]
                    d[i] = adb[i]
            else:
                return False               # the origin is inside: the hulls overlap
        n2 = dot3(d, d)
        if n2 < 1e-300 or n2 != n2:
            return False                   # the origin on the simplex: touching (or degenerate)
    return False


cdef inline void place(const double* T, const double* p, double* out) noexcept nogil:
    """out = T p (T: a 4x4 row-major pose, NULL: the identity)."""
    cdef int r
    for r in range(3):
        out[r] = p[r] if T == NULL else T[4 * r] * p[0] + T[4 * r + 1] * p[1] + T[4 * r + 2] * p[2] + T[4 * r + 3]


cdef int links_apart(const double* F, int n, const double* verts, const Py_ssize_t* start, const int* frame,
                     const double* bound, const Py_ssize_t* link_start, const int* link_parts, int u, int v,
                     double* buf) noexcept nogil:
    """1 if every part of link u is apart from every part of link v at the frames F ((n+1) x 16): their
    capsules apart, or else a separating plane (``apart``)."""
    cdef int pu, pv, k, l, i, na, nb
    cdef bint placed
    cdef const double* Tu
    cdef const double* Tv
    cdef double* A = buf
    cdef double* B
    cdef double cu[6]
    cdef double cv[6]
    cdef double rr
    cdef double dc[3]
    for pu in range(<int>link_start[u], <int>link_start[u + 1]):
        k = link_parts[pu]
        na = <int>(start[k + 1] - start[k])
        Tu = F + 16 * (frame[k] - 1) if frame[k] > 0 else NULL
        place(Tu, bound + 7 * k, cu)
        place(Tu, bound + 7 * k + 3, cu + 3)
        placed = False
        B = buf + 3 * na
        for pv in range(<int>link_start[v], <int>link_start[v + 1]):
            l = link_parts[pv]
            Tv = F + 16 * (frame[l] - 1) if frame[l] > 0 else NULL
            place(Tv, bound + 7 * l, cv)
            place(Tv, bound + 7 * l + 3, cv + 3)
            rr = bound[7 * k + 6] + bound[7 * l + 6]
            if segment_distance2(cu, cu + 3, cv, cv + 3) > rr * rr:
                continue
            if not placed:
                for i in range(na):
                    place(Tu, verts + 3 * (start[k] + i), A + 3 * i)
                placed = True
            nb = <int>(start[l + 1] - start[l])
            for i in range(nb):
                place(Tv, verts + 3 * (start[l] + i), B + 3 * i)
            for i in range(3):
                dc[i] = cu[i] + cu[3 + i] - cv[i] - cv[3 + i]
            if not apart(A, na, B, nb, dc):
                return 0
    return 1


def parts_apart(frames, verts, start, frame, bound, link_start, link_parts, queries, int threads=0):
    """uint8 (Q,): per query (row, link u, link v) of ``queries`` (Q, 3), 1 when every convex part of link
    u is proven apart from every part of link v (a separating plane each) at the frames ``frames[row]``
    ((M, n+1, 4, 4) as ``Robot.frames_at`` gives them); 0: not proven (touching, overlapping, or the
    search gave up), for an exact check to decide.

    Parts: ``verts`` (H, 3) the parts' points in their frames' coordinates at q = 0, part k's rows
    ``start[k]:start[k+1]``, ``frame[k]`` its frame index (0: the base); link l's parts are
    ``link_parts[link_start[l]:link_start[l+1]]``."""
    cdef cnp.ndarray Fa = np.ascontiguousarray(frames, dtype=np.float64)
    cdef cnp.ndarray Va = np.ascontiguousarray(verts, dtype=np.float64)
    cdef cnp.ndarray Sa = np.ascontiguousarray(start, dtype=np.intp)
    cdef cnp.ndarray Ka = np.ascontiguousarray(frame, dtype=np.intc)
    cdef cnp.ndarray Ba = np.ascontiguousarray(bound, dtype=np.float64)
    cdef cnp.ndarray La = np.ascontiguousarray(link_start, dtype=np.intp)
    cdef cnp.ndarray Pa = np.ascontiguousarray(link_parts, dtype=np.intc)
    cdef cnp.ndarray Qa = np.ascontiguousarray(queries, dtype=np.intc)
    if Fa.ndim != 4 or Fa.shape[2] != 4 or Fa.shape[3] != 4 or Va.ndim != 2 or Va.shape[1] != 3 \
            or Qa.ndim != 2 or Qa.shape[1] != 3 or Sa.ndim != 1 or Ka.shape[0] != Sa.shape[0] - 1 \
            or Ba.ndim != 2 or Ba.shape[0] != Ka.shape[0] or Ba.shape[1] != 7:
        raise ValueError("parts_apart: expected frames (M, n+1, 4, 4), verts (H, 3), start (K+1,), frame (K,), "
                         "bound (K, 7), queries (Q, 3)")
    cdef int n = <int>Fa.shape[1] - 1, K = <int>Ka.shape[0], L = <int>La.shape[0] - 1
    cdef Py_ssize_t M = Fa.shape[0], Q = Qa.shape[0], j
    if K and (Sa[0] != 0 or Sa[K] != Va.shape[0] or (np.diff(Sa) < 1).any() or Ka.min() < 0 or Ka.max() > n):
        raise ValueError("parts_apart: part rows or frames out of range")
    if L < 0 or La[0] != 0 or La[L] != Pa.shape[0] or (np.diff(La) < 0).any() or (Pa.shape[0] and (Pa.min() < 0 or Pa.max() >= K)):
        raise ValueError("parts_apart: link parts out of range")
    if Q and (Qa[:, 0].min() < 0 or Qa[:, 0].max() >= M or Qa[:, 1:].min() < 0 or Qa[:, 1:].max() >= L):
        raise ValueError("parts_apart: queries out of range")
    cdef cnp.ndarray out = np.zeros(Q, dtype=np.uint8)
    cdef Py_ssize_t most = int(np.diff(Sa).max()) if K else 0
    cdef const double* F = <const double*>cnp.PyArray_DATA(Fa)
    cdef const double* V = <const double*>cnp.PyArray_DATA(Va)
    cdef const Py_ssize_t* S = <const Py_ssize_t*>cnp.PyArray_DATA(Sa)
    cdef const int* Kf = <const int*>cnp.PyArray_DATA(Ka)
    cdef const double* Bs = <const double*>cnp.PyArray_DATA(Ba)
    cdef const Py_ssize_t* Ls = <const Py_ssize_t*>cnp.PyArray_DATA(La)
    cdef const int* Lp = <const int*>cnp.PyArray_DATA(Pa)
    cdef const int* Qp = <const int*>cnp.PyArray_DATA(Qa)
    cdef unsigned char* O = <unsigned char*>cnp.PyArray_DATA(out)
    cdef double* buf
    cdef int nt
    with nogil:
        nt = batch_threads(threads, Q, 64) if Q > 64 else 1
        for j in prange(Q, num_threads=nt, schedule="dynamic", chunksize=16):
            buf = <double*>malloc(sizeof(double) * 6 * (most + 1))
            if buf != NULL:
                O[j] = <unsigned char>links_apart(F + 16 * (n + 1) * Qp[3 * j], n, V, S, Kf, Bs, Ls, Lp,
                                                  Qp[3 * j + 1], Qp[3 * j + 2], buf)
                free(buf)
    return out
