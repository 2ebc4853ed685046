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
from libc.math cimport sqrt
from cython.parallel cimport prange, threadid
from robkin.compiled.collision.segments cimport segment_distance2
from robkin.compiled.runtime.threads cimport batch_threads

import numpy as np

cnp.import_array()

cdef enum:
    # GJK steps before giving up (and answering "not proven apart", which the caller checks exactly)
    GJK_STEPS = 64
    # parts of a link placed once per link pair (``links_apart``; the model makes up to 8)
    MAX_PARTS = 32
    # part pairs whose capsules meet, kept per link pair to be tried deepest overlap first (more are tried
    # as found)
    MAX_CANDIDATES = 128


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


cdef inline void place(const double* T, const double* p, double* out) noexcept nogil:
    """out = T p (T: a 4x4 row-major pose, NULL: the identity)."""
    cdef int r
    for r in range(3):
        out[r] = p[r] if T == NULL else T[4 * r] * p[0] + T[4 * r + 1] * p[1] + T[4 * r + 2] * p[2] + T[4 * r + 3]


cdef inline double support_one(const double* V, int nv, const double* T, const double* d, double* w) noexcept nogil:
    """w = the point of T V (V: nv local points, T: a 4x4 row-major pose, NULL: the identity) farthest along
    the direction d (world); returns d . w. The direction is turned into V's frame (R^T d) instead of
    moving every point: one 3-term dot product a point."""
    cdef double dl[3]
    cdef int i, best_i = 0, r
    cdef double best = -1e300, x
    if T == NULL:
        dl[0] = d[0]
        dl[1] = d[1]
        dl[2] = d[2]
    else:
        for r in range(3):
            dl[r] = T[r] * d[0] + T[4 + r] * d[1] + T[8 + r] * d[2]
    for i in range(nv):
        x = V[3 * i] * dl[0] + V[3 * i + 1] * dl[1] + V[3 * i + 2] * dl[2]
        if x > best:
            best = x
            best_i = i
    place(T, V + 3 * best_i, w)
    return dot3(w, d)


cdef double support_gap(const double* A, int na, const double* TA, const double* B, int nb, const double* TB,
                        const double* d, double* w) noexcept nogil:
    """w = the point of A - B farthest along d (A's farthest minus B's nearest; A and B local points placed
    by the poses TA, TB); returns d . w."""
    cdef double wa[3]
    cdef double wb[3]
    cdef double nd[3]
    cdef int i
    for i in range(3):
        nd[i] = -d[i]
    support_one(A, na, TA, d, wa)
    support_one(B, nb, TB, nd, wb)
    for i in range(3):
        w[i] = wa[i] - wb[i]
    return dot3(w, d)


cdef bint apart(const double* A, int na, const double* TA, const double* B, int nb, const double* TB,
               const double* start, double* hint, const double* TH, int steps, double margin) noexcept nogil:
    """True only when a plane separates the convex hulls of the points A and B ((k, 3) each, in their own
    frames, placed by the poses TA and TB):
    a direction d with max over A of d.a < min over B of d.b, found by GJK on A - B. Anything else
    (touching, overlapping, a degenerate step, too many steps) is False: "not proven apart". ``start``:
    the first search direction (B's centre to A's: most pairs are proven apart at the first step).
    ``hint`` (3, in the frame TH; zero: none): a direction that separated this pair before, tried first,
    replaced by the separating direction found. TH is the frame of the body before B's (B's joint axis
    is fixed in it): a plane along that axis stays a separating plane whatever the joint's angle, so the
    hint often holds across the configurations of a batch. ``steps``: GJK steps before giving up.
    ``margin`` >= 0: the plane must leave at least that gap (length units), which proves the hulls at
    least ``margin`` apart."""
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
    if hint[0] != 0.0 or hint[1] != 0.0 or hint[2] != 0.0:
        for i in range(3):
            d[i] = hint[i] if TH == NULL else TH[4 * i] * hint[0] + TH[4 * i + 1] * hint[1] + TH[4 * i + 2] * hint[2]
        if support_gap(A, na, TA, B, nb, TB, d, w) < -margin * sqrt(dot3(d, d)):
            return True                    # the remembered plane still separates them
    for i in range(3):
        d[i] = start[i]
    if dot3(d, d) < 1e-300:
        d[0] = 1.0
    for step in range(steps):
        if support_gap(A, na, TA, B, nb, TB, d, w) < -margin * sqrt(dot3(d, d)):
            for i in range(3):             # A's farthest along d is short of B's nearest: apart
                hint[i] = d[i] if TH == NULL else TH[i] * d[0] + TH[4 + i] * d[1] + TH[8 + i] * d[2]
            return True
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


cdef int links_apart(const double* F, int n, const double* verts, const Py_ssize_t* start, const int* frame,
                     const double* bound, const Py_ssize_t* link_start, const int* link_parts,
                     int u, int v, int K, double* hints, double margin) noexcept nogil:
    """1 if link u is apart from link v at the frames F ((n+1) x 16): every part of one apart from every
    part of the other (their capsules apart, or a separating plane, ``apart``). ``hints``: the thread's
    remembered directions, 3 per ordered part pair (K x K). ``margin``: each gap at least that (``apart``).
    (No test of the two links' whole hulls first: where the capsules meet and no pair map clears the
    pair, such a plane was never found on the Panda, UR5 or iiwa, 2026-11-29, and cost a tenth.)"""
    cdef int pu, pv, k, l, i, na, nb
    cdef const double* Tu
    cdef const double* Tv
    cdef double cu[6]
    cdef double cv[6]
    cdef double rr
    cdef double dc[3]
    # the links' frames: all parts of a link are on its body (the first part's frame)
    k = link_parts[link_start[u]]
    l = link_parts[link_start[v]]
    Tu = F + 16 * (frame[k] - 1) if frame[k] > 0 else NULL
    Tv = F + 16 * (frame[l] - 1) if frame[l] > 0 else NULL
    # the frame the hints are kept in: the body before v's (see ``apart``)
    cdef const double* Th = F + 16 * (frame[l] - 2) if frame[l] > 1 else NULL
    # every part pair: capsules apart (bounding spheres first), or a plane between them. Link u's
    # part capsules are placed once (up to MAX_PARTS; a link with more places them pair by pair). The
    # pairs whose capsules meet are tried deepest overlap first: where the links do touch, the first
    # GJK search is then most often the one that fails, and ends the pair's test (a configuration in
    # collision cost ~2.5x a free one's test when they were tried in the parts' order, UR5 IK answers)
    cdef int ck[MAX_CANDIDATES]
    cdef int cl[MAX_CANDIDATES]
    cdef double cdepth[MAX_CANDIDATES]
    cdef double cdir[3 * MAX_CANDIDATES]
    cdef int nc = 0, a, b
    cdef double t
    cdef double PU[MAX_PARTS * 7]
    cdef int nu = <int>(link_start[u + 1] - link_start[u]), j
    cdef bint cached = nu <= MAX_PARTS
    cdef double x, y, z, s
    if cached:
        for j in range(nu):
            k = link_parts[link_start[u] + j]
            place(Tu, bound + 7 * k, PU + 7 * j)
            place(Tu, bound + 7 * k + 3, PU + 7 * j + 3)
            x = bound[7 * k + 3] - bound[7 * k]
            y = bound[7 * k + 4] - bound[7 * k + 1]
            z = bound[7 * k + 5] - bound[7 * k + 2]
            PU[7 * j + 6] = 0.5 * sqrt(x * x + y * y + z * z) + bound[7 * k + 6]     # bounding sphere's radius
    for pv in range(<int>link_start[v], <int>link_start[v + 1]):
        l = link_parts[pv]
        nb = <int>(start[l + 1] - start[l])
        place(Tv, bound + 7 * l, cv)
        place(Tv, bound + 7 * l + 3, cv + 3)
        x = bound[7 * l + 3] - bound[7 * l]
        y = bound[7 * l + 4] - bound[7 * l + 1]
        z = bound[7 * l + 5] - bound[7 * l + 2]
        s = 0.5 * sqrt(x * x + y * y + z * z) + bound[7 * l + 6] + margin
        for pu in range(<int>link_start[u], <int>link_start[u + 1]):
            k = link_parts[pu]
            na = <int>(start[k + 1] - start[k])
            if cached:
                j = pu - <int>link_start[u]
                for i in range(6):
                    cu[i] = PU[7 * j + i]
                # the parts' bounding spheres apart: so are their capsules (no segment distance needed)
                x = cu[0] + cu[3] - cv[0] - cv[3]
                y = cu[1] + cu[4] - cv[1] - cv[4]
                z = cu[2] + cu[5] - cv[2] - cv[5]
                if x * x + y * y + z * z > 4.0 * (s + PU[7 * j + 6]) * (s + PU[7 * j + 6]):
                    continue
            else:
                place(Tu, bound + 7 * k, cu)
                place(Tu, bound + 7 * k + 3, cu + 3)
            rr = bound[7 * k + 6] + bound[7 * l + 6] + margin
            t = segment_distance2(cu, cu + 3, cv, cv + 3)
            if t > rr * rr:
                continue
            for i in range(3):
                dc[i] = cu[i] + cu[3 + i] - cv[i] - cv[3 + i]
            if nc < MAX_CANDIDATES:           # kept, and inserted by depth (deepest first)
                t = rr - sqrt(t)
                a = nc
                while a > 0 and cdepth[a - 1] < t:
                    ck[a] = ck[a - 1]
                    cl[a] = cl[a - 1]
                    cdepth[a] = cdepth[a - 1]
                    for i in range(3):
                        cdir[3 * a + i] = cdir[3 * a - 3 + i]
                    a -= 1
                ck[a] = k
                cl[a] = l
                cdepth[a] = t
                for i in range(3):
                    cdir[3 * a + i] = dc[i]
                nc += 1
            elif not apart(verts + 3 * start[k], na, Tu, verts + 3 * start[l], nb, Tv, dc,
                           hints + 3 * (k * K + l), Th, GJK_STEPS, margin):
                return 0
    for b in range(nc):
        k = ck[b]
        l = cl[b]
        if not apart(verts + 3 * start[k], <int>(start[k + 1] - start[k]), Tu, verts + 3 * start[l],
                     <int>(start[l + 1] - start[l]), Tv, cdir + 3 * b, hints + 3 * (k * K + l), Th, GJK_STEPS,
                     margin):
            return 0
    return 1


cdef int check_layout(const Py_ssize_t* S, int K, Py_ssize_t nv, const int* Kf, int n, const Py_ssize_t* Ls, int L,
                      const int* Lp, Py_ssize_t np_, const int* Qp, Py_ssize_t Q, Py_ssize_t M) noexcept nogil:
    """0 when ``parts_apart``'s index arrays are consistent, else the number of the first problem (1: part
    rows or frames, 2: link parts, 3: a link without parts, 4: a link's parts on two frames, 5: queries)."""
    cdef Py_ssize_t k, j
    if K and (S[0] != 0 or S[K] != nv):
        return 1
    for k in range(K):
        if S[k + 1] - S[k] < 1 or Kf[k] < 0 or Kf[k] > n:
            return 1
    if L < 0 or Ls[0] != 0 or Ls[L] != np_:
        return 2
    for k in range(np_):
        if Lp[k] < 0 or Lp[k] >= K:
            return 2
    for k in range(L):
        if Ls[k + 1] < Ls[k]:
            return 2
    for k in range(L):
        if Ls[k + 1] == Ls[k]:
            return 3
    for k in range(L):
        for j in range(Ls[k] + 1, Ls[k + 1]):
            if Kf[Lp[j]] != Kf[Lp[Ls[k]]]:
                return 4
    for k in range(Q):
        if Qp[3 * k] < 0 or Qp[3 * k] >= M or Qp[3 * k + 1] < 0 or Qp[3 * k + 1] >= L or Qp[3 * k + 2] < 0 \
                or Qp[3 * k + 2] >= L:
            return 5
    return 0


cdef bint rows_sorted(const int* Qp, Py_ssize_t Q) noexcept nogil:
    cdef Py_ssize_t k
    for k in range(1, Q):
        if Qp[3 * k] < Qp[3 * k - 3]:
            return False
    return True


cdef Py_ssize_t row_starts(const int* Qp, const Py_ssize_t* order, Py_ssize_t Q, Py_ssize_t* rows) noexcept nogil:
    """rows[g] = where row group g begins in ``order`` (rows[R] = Q); returns R, the number of groups."""
    cdef Py_ssize_t k, R = 0
    for k in range(Q):
        if k == 0 or Qp[3 * order[k]] != Qp[3 * order[k - 1]]:
            rows[R] = k
            R += 1
    rows[R] = Q
    return R


def parts_apart(frames, verts, start, frame, bound, link_start, link_parts, queries,
                int threads=0, double margin=0.0):
    """uint8 (Q,): per query (row, link u, link v) of ``queries`` (Q, 3), 1 when every convex part of link
    u is proven apart from every part of link v (a separating plane each) at the frames ``frames[row]``
    ((M, n+1, 4, 4) as ``Robot.frames_at`` gives them); 0: not proven (touching, overlapping, or the
    search gave up), for an exact check to decide. The queries of one row (one configuration) are tried
    in their order until one is not proven: the row's later queries are left 0, untried (the
    configuration is not cleared either way; put the likeliest contact first). ``margin`` >= 0 (length
    units): 1 then proves the two links at least that far apart (every plane leaves that gap).

    Parts: ``verts`` (H, 3) the parts' points in their frames' coordinates at q = 0, part k's rows
    ``start[k]:start[k+1]``, ``frame[k]`` its frame index (0: the base); link l's parts are
    ``link_parts[link_start[l]:link_start[l+1]]`` (all on one frame, the link's body, at least one each);
    ``bound`` (K, 7) a segment [a, b] and radius around each part's points (the capsule tested first; the
    segments' middles start the search)."""
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
    cdef Py_ssize_t M = Fa.shape[0], Q = Qa.shape[0], j, g, R
    if Sa.shape[0] != K + 1 or La.ndim != 1 or La.shape[0] < 1 or Pa.ndim != 1:
        raise ValueError("parts_apart: start (K+1,), link_start (L+1,), link_parts (P,)")
    if not margin >= 0.0:
        raise ValueError("parts_apart: margin must be >= 0")
    # the index checks as C loops (a few us; numpy's would cost ~50 us a call, most of a small batch's time)
    cdef int problem = check_layout(<const Py_ssize_t*>cnp.PyArray_DATA(Sa), K, Va.shape[0],
                                    <const int*>cnp.PyArray_DATA(Ka), n,
                                    <const Py_ssize_t*>cnp.PyArray_DATA(La), L,
                                    <const int*>cnp.PyArray_DATA(Pa), Pa.shape[0],
                                    <const int*>cnp.PyArray_DATA(Qa), Q, M)
    if problem:
        raise ValueError(("parts_apart: part rows or frames out of range", "parts_apart: link parts out of range",
                          "parts_apart: every link needs parts",
                          "parts_apart: a link's parts must share one frame",
                          "parts_apart: queries out of range")[problem - 1])
    cdef cnp.ndarray out = np.zeros(Q, dtype=np.uint8)
    cdef const double* F = <const double*>cnp.PyArray_DATA(Fa)
    cdef const double* V = <const double*>cnp.PyArray_DATA(Va)
    cdef const Py_ssize_t* S = <const Py_ssize_t*>cnp.PyArray_DATA(Sa)
    cdef const int* Kf = <const int*>cnp.PyArray_DATA(Ka)
    cdef const double* Bs = <const double*>cnp.PyArray_DATA(Ba)
    cdef const Py_ssize_t* Ls = <const Py_ssize_t*>cnp.PyArray_DATA(La)
    cdef const int* Lp = <const int*>cnp.PyArray_DATA(Pa)
    cdef const int* Qp = <const int*>cnp.PyArray_DATA(Qa)
    cdef unsigned char* O = <unsigned char*>cnp.PyArray_DATA(out)
    cdef int nt
    with nogil:
        nt = batch_threads(threads, Q, 64) if Q > 64 else 1
    # each thread's remembered separating directions (see ``apart``): its own rows, no sharing
    cdef Py_ssize_t per = 3 * K * K
    cdef cnp.ndarray hint_a = np.zeros(max(nt, 1) * per, dtype=np.float64)
    cdef double* HT = <double*>cnp.PyArray_DATA(hint_a)
    # the queries row by row (their order within a row kept): a row stops at its first pair not proven
    cdef cnp.ndarray order_a = np.argsort(Qa[:, 0], kind="stable").astype(np.intp) if not rows_sorted(
        <const int*>cnp.PyArray_DATA(Qa), Q) else np.arange(Q, dtype=np.intp)
    cdef cnp.ndarray rows_a = np.empty(Q + 1, dtype=np.intp)
    R = row_starts(<const int*>cnp.PyArray_DATA(Qa), <const Py_ssize_t*>cnp.PyArray_DATA(order_a), Q,
                   <Py_ssize_t*>cnp.PyArray_DATA(rows_a))
    cdef const Py_ssize_t* od = <const Py_ssize_t*>cnp.PyArray_DATA(order_a)
    cdef const Py_ssize_t* rw = <const Py_ssize_t*>cnp.PyArray_DATA(rows_a)
    with nogil:
        for g in prange(R, num_threads=nt, schedule="dynamic", chunksize=4):
            for j in range(rw[g], rw[g + 1]):
                O[od[j]] = <unsigned char>links_apart(F + 16 * (n + 1) * Qp[3 * od[j]], n, V, S, Kf, Bs, Ls, Lp,
                                                      Qp[3 * od[j] + 1], Qp[3 * od[j] + 2], K,
                                                      HT + per * threadid(), margin)
                if O[od[j]] == 0:
                    break
    return out
