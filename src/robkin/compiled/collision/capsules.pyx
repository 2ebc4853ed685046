# cython: language_level=3
"""Batch self-collision of capsule models: the chain's frames (``fk.pxd``'s walk) and, per configuration,
the segment-segment distances of the capsule pairs that are checked.

A capsule is the set of points within ``radius`` of a segment [a, b] fixed to one GJD frame: ``caps``
(C, 7) holds a (3), b (3) in that frame's coordinates at q = 0 and the radius; ``frame`` (C,) the frame
index k: 0 for the base (never moves), k in 1..n for body k (moves with GJD frame k, index k - 1 of the
frames along the chain). ``pairs`` (P, 2) lists the capsule pairs to check. Two capsules collide when
their segments are closer than the sum of the radii (touching counts as a collision).

Configurations are walked in blocks of ``BLOCK`` (the chain's frames of a block are computed together,
then each configuration's capsules are moved and its pairs checked), blocks split over threads
(``prange``, ``threads`` 0: automatic, ``robkin.threads``); every configuration gets the same bits
whatever the thread count. Like ``fk.pyx`` the functions return None unless q is a C-contiguous float64
array (n,) or (N, n) of finite values; the Python wrapper (``robkin.self_collision.model``) validates.
"""

cimport numpy as cnp
from cython.parallel cimport prange
from libc.stdlib cimport malloc, free
from libc.math cimport sqrt
from robkin.compiled.chain.fk cimport BLOCK, Chain, finite_block, frame_poses, usable_layout
from robkin.compiled.runtime.threads cimport batch_threads

import numpy as np

cnp.import_array()

cdef enum:
    # blocks a thread must get before a batch is split (a block of 32 Panda configurations is ~10 us)
    MIN_BLOCKS_PER_THREAD = 8


cdef inline double clamp01(double x) noexcept nogil:
    return 0.0 if x < 0.0 else (1.0 if x > 1.0 else x)


cdef inline double segment_distance2(const double* p1, const double* q1, const double* p2,
                                     const double* q2) noexcept nogil:
    """Squared distance between the segments [p1, q1] and [p2, q2] (Ericson, Real-Time Collision
    Detection, 5.1.9), degenerate segments (points) included."""
    cdef double d1[3]
    cdef double d2[3]
    cdef double r[3]
    cdef double a = 0.0, e = 0.0, f = 0.0, c = 0.0, b = 0.0, s, t, denom, x, out = 0.0
    cdef int k
    for k in range(3):
        d1[k] = q1[k] - p1[k]
        d2[k] = q2[k] - p2[k]
        r[k] = p1[k] - p2[k]
        a += d1[k] * d1[k]
        e += d2[k] * d2[k]
        f += d2[k] * r[k]
        c += d1[k] * r[k]
        b += d1[k] * d2[k]
    # 1e-300: a segment of zero length (a sphere) is a point; any real length squared is far above
    if a <= 1e-300 and e <= 1e-300:
        s = 0.0
        t = 0.0
    elif a <= 1e-300:
        s = 0.0
        t = clamp01(f / e)
    elif e <= 1e-300:
        t = 0.0
        s = clamp01(-c / a)
    else:
        denom = a * e - b * b
        s = clamp01((b * f - c * e) / denom) if denom > 0.0 else 0.0
        t = (b * s + f) / e
        if t < 0.0:
            t = 0.0
            s = clamp01(-c / a)
        elif t > 1.0:
            t = 1.0
            s = clamp01((b - c) / a)
    for k in range(3):
        x = (p1[k] + d1[k] * s) - (p2[k] + d2[k] * t)
        out += x * x
    return out


cdef inline void move_capsules(const double* F, int n, const double* caps, const int* frame, int C,
                               double* W) noexcept nogil:
    """W (C x 6) = the capsules' end points at one configuration whose frames are F ((n+1) x 16)."""
    cdef int i, k, r
    cdef const double* T
    cdef const double* p
    for i in range(C):
        k = frame[i]
        for r in range(2):
            p = caps + 7 * i + 3 * r
            if k == 0:
                W[6 * i + 3 * r] = p[0]
                W[6 * i + 3 * r + 1] = p[1]
                W[6 * i + 3 * r + 2] = p[2]
            else:
                T = F + 16 * (k - 1)
                W[6 * i + 3 * r] = T[0] * p[0] + T[1] * p[1] + T[2] * p[2] + T[3]
                W[6 * i + 3 * r + 1] = T[4] * p[0] + T[5] * p[1] + T[6] * p[2] + T[7]
                W[6 * i + 3 * r + 2] = T[8] * p[0] + T[9] * p[1] + T[10] * p[2] + T[11]


cdef int check_block(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t N,
                     Py_ssize_t j, const double* caps, const int* frame, int C, const int* pairs, int P,
                     unsigned char* hit, double* dist) noexcept nogil:
    """Block j of the batch: hit[b] (1: some pair collides) if ``hit``, else dist (N x P) signed distances
    (segment distance minus both radii). Returns 1 if the block holds a value that is not finite, -1 if
    memory ran out, else 0."""
    cdef Py_ssize_t k0 = BLOCK * j
    cdef int m = <int>(N - k0 if N - k0 < BLOCK else BLOCK), b, p, u, v
    cdef double* F
    cdef double* W
    cdef double* S
    cdef double rr, d2, x, y, z, s
    cdef int i
    if not finite_block(Q, n, N, j):
        return 1
    F = <double*>malloc(sizeof(double) * (16 * (n + 1) * m + 6 * C + C))
    if F == NULL:
        return -1
    W = F + 16 * (n + 1) * m
    S = W + 6 * C
    for i in range(C):
        # each capsule's bounding sphere about its segment's midpoint: half the length plus the radius
        x = caps[7 * i + 3] - caps[7 * i]
        y = caps[7 * i + 4] - caps[7 * i + 1]
        z = caps[7 * i + 5] - caps[7 * i + 2]
        S[i] = 0.5 * sqrt(x * x + y * y + z * z) + caps[7 * i + 6]
    frame_poses(L, rev, n, Q + n * k0, m, F)
    for b in range(m):
        move_capsules(F + 16 * (n + 1) * b, n, caps, frame, C, W)
        if hit != NULL:
            hit[k0 + b] = 0
            for p in range(P):
                u = pairs[2 * p]
                v = pairs[2 * p + 1]
                # bounding spheres apart: the capsules are (no segment distance needed)
                x = W[6 * u] + W[6 * u + 3] - W[6 * v] - W[6 * v + 3]
                y = W[6 * u + 1] + W[6 * u + 4] - W[6 * v + 1] - W[6 * v + 4]
                z = W[6 * u + 2] + W[6 * u + 5] - W[6 * v + 2] - W[6 * v + 5]
                s = S[u] + S[v]
                if x * x + y * y + z * z > 4.0 * s * s:
                    continue
                rr = caps[7 * u + 6] + caps[7 * v + 6]
                if segment_distance2(W + 6 * u, W + 6 * u + 3, W + 6 * v, W + 6 * v + 3) <= rr * rr:
                    hit[k0 + b] = 1
                    break
        else:
            for p in range(P):
                u = pairs[2 * p]
                v = pairs[2 * p + 1]
                d2 = segment_distance2(W + 6 * u, W + 6 * u + 3, W + 6 * v, W + 6 * v + 3)
                dist[(k0 + b) * P + p] = sqrt(d2) - caps[7 * u + 6] - caps[7 * v + 6]
    free(F)
    return 0


cdef object run(Chain chain, q, caps, frame, pairs, int threads, bint distances):
    cdef int n = chain.n
    cdef cnp.ndarray ca = np.ascontiguousarray(caps, dtype=np.float64)
    cdef cnp.ndarray fa = np.ascontiguousarray(frame, dtype=np.intc)
    cdef cnp.ndarray pa = np.ascontiguousarray(pairs, dtype=np.intc)
    cdef int C, P, nt, status
    cdef Py_ssize_t N, j, blocks, bad = 0, oom = 0
    cdef cnp.ndarray out
    if ca.ndim != 2 or ca.shape[1] != 7 or fa.ndim != 1 or fa.shape[0] != ca.shape[0] or pa.ndim != 2 \
            or pa.shape[1] != 2:
        raise ValueError("capsules: expected caps (C, 7), frame (C,), pairs (P, 2)")
    C = <int>ca.shape[0]
    P = <int>pa.shape[0]
    if C and (fa.min() < 0 or fa.max() > n):
        raise ValueError(f"capsules: frame indices must be in 0..{n}")
    if P and (pa.min() < 0 or pa.max() >= C):
        raise ValueError(f"capsules: pair indices must be in 0..{C - 1}")
    if not usable_layout(q, n):
        return None
    N = cnp.PyArray_SIZE(q) // n
    out = np.empty((N, P), dtype=np.float64) if distances else np.empty(N, dtype=np.uint8)
    cdef const double* Q = <const double*>cnp.PyArray_DATA(q)
    cdef const double* Cp = <const double*>cnp.PyArray_DATA(ca)
    cdef const int* Fp = <const int*>cnp.PyArray_DATA(fa)
    cdef const int* Pp = <const int*>cnp.PyArray_DATA(pa)
    cdef unsigned char* H = NULL if distances else <unsigned char*>cnp.PyArray_DATA(out)
    cdef double* D = <double*>cnp.PyArray_DATA(out) if distances else NULL
    blocks = (N + BLOCK - 1) // BLOCK
    with nogil:
        nt = batch_threads(threads, blocks, MIN_BLOCKS_PER_THREAD) if blocks > 1 else 1
        if nt > 1:
            for j in prange(blocks, num_threads=nt, schedule="dynamic", chunksize=2):
                status = check_block(chain.L, chain.rev, n, Q, N, j, Cp, Fp, C, Pp, P, H, D)
                if status > 0:
                    bad += 1
                elif status < 0:
                    oom += 1
        else:
            for j in range(blocks):
                status = check_block(chain.L, chain.rev, n, Q, N, j, Cp, Fp, C, Pp, P, H, D)
                if status > 0:
                    bad += 1
                    break
                elif status < 0:
                    oom += 1
                    break
    if oom:
        raise MemoryError("capsules: no memory for a block of frames")
    if bad:
        return None
    return out


def collide(Chain chain, q, caps, frame, pairs, int threads=0):
    """uint8 (N,) (1: some checked pair of capsules touches or overlaps) for q (N, n) (or (1,) for q (n,));
    None if q is not a C-contiguous float64 array of finite values (see the module doc)."""
    return run(chain, q, caps, frame, pairs, threads, False)


def distances(Chain chain, q, caps, frame, pairs, int threads=0):
    """float64 (N, P): per configuration and checked pair, the distance between the two capsules
    (segment distance minus both radii; negative: they overlap by that much). None as ``collide``."""
    return run(chain, q, caps, frame, pairs, threads, True)


def segment_distance(p1, q1, p2, q2):
    """The distance between the segments [p1, q1] and [p2, q2] (each (3,)), as the kernels compute it."""
    cdef double a[12]
    cdef int k
    for k in range(3):
        a[k] = float(p1[k])
        a[3 + k] = float(q1[k])
        a[6 + k] = float(p2[k])
        a[9 + k] = float(q2[k])
    return sqrt(segment_distance2(a, a + 3, a + 6, a + 9))


# ---------------------------------------------------------------- convex parts: a separating-plane test

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


cdef bint apart(const double* A, int na, const double* B, int nb) noexcept nogil:
    """True only when a plane separates the convex hulls of the points A and B (both (k, 3), one frame):
    a direction d with max over A of d.a < min over B of d.b, found by GJK on A - B. Anything else
    (touching, overlapping, a degenerate step, too many steps) is False: "not proven apart"."""
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
        d[i] = A[i] - B[i]
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
                     const double* sphere, const Py_ssize_t* link_start, const int* link_parts, int u, int v,
                     double* buf) noexcept nogil:
    """1 if every part of link u is apart from every part of link v at the frames F ((n+1) x 16): their
    bounding spheres apart, or else a separating plane (``apart``)."""
    cdef int pu, pv, k, l, i, na, nb
    cdef bint placed
    cdef const double* Tu
    cdef const double* Tv
    cdef double* A = buf
    cdef double* B
    cdef double cu[3]
    cdef double cv[3]
    cdef double x, y, z, rr
    for pu in range(<int>link_start[u], <int>link_start[u + 1]):
        k = link_parts[pu]
        na = <int>(start[k + 1] - start[k])
        Tu = F + 16 * (frame[k] - 1) if frame[k] > 0 else NULL
        place(Tu, sphere + 4 * k, cu)
        placed = False
        B = buf + 3 * na
        for pv in range(<int>link_start[v], <int>link_start[v + 1]):
            l = link_parts[pv]
            Tv = F + 16 * (frame[l] - 1) if frame[l] > 0 else NULL
            place(Tv, sphere + 4 * l, cv)
            x = cu[0] - cv[0]
            y = cu[1] - cv[1]
            z = cu[2] - cv[2]
            rr = sphere[4 * k + 3] + sphere[4 * l + 3]
            if x * x + y * y + z * z > rr * rr:
                continue
            if not placed:
                for i in range(na):
                    place(Tu, verts + 3 * (start[k] + i), A + 3 * i)
                placed = True
            nb = <int>(start[l + 1] - start[l])
            for i in range(nb):
                place(Tv, verts + 3 * (start[l] + i), B + 3 * i)
            if not apart(A, na, B, nb):
                return 0
    return 1


def parts_apart(frames, verts, start, frame, sphere, link_start, link_parts, queries, int threads=0):
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
    cdef cnp.ndarray Ba = np.ascontiguousarray(sphere, dtype=np.float64)
    cdef cnp.ndarray La = np.ascontiguousarray(link_start, dtype=np.intp)
    cdef cnp.ndarray Pa = np.ascontiguousarray(link_parts, dtype=np.intc)
    cdef cnp.ndarray Qa = np.ascontiguousarray(queries, dtype=np.intc)
    if Fa.ndim != 4 or Fa.shape[2] != 4 or Fa.shape[3] != 4 or Va.ndim != 2 or Va.shape[1] != 3 \
            or Qa.ndim != 2 or Qa.shape[1] != 3 or Sa.ndim != 1 or Ka.shape[0] != Sa.shape[0] - 1 \
            or Ba.ndim != 2 or Ba.shape[0] != Ka.shape[0] or Ba.shape[1] != 4:
        raise ValueError("parts_apart: expected frames (M, n+1, 4, 4), verts (H, 3), start (K+1,), frame (K,), "
                         "sphere (K, 4), queries (Q, 3)")
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
