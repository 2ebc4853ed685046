# cython: language_level=3
"""Batch self-collision of capsule models: the chain's frames (``fk.pxd``'s walk) and, per configuration,
the segment-segment distances of the capsule pairs that are checked.

A capsule is the set of points within ``radius`` of a segment [a, b] fixed to one GJD frame: ``caps``
(C, 7) holds a (3), b (3) in that frame's coordinates at q = 0 and the radius; ``frame`` (C,) the frame
index k: 0 for the base (never moves), k in 1..n for body k (moves with GJD frame k, index k - 1 of the
frames along the chain). ``pairs`` (P, 2) lists the capsule pairs to check. Two capsules collide when
their segments are closer than the sum of the radii (touching counts as a collision).

``overlaps`` is the first pass of the 'parts' level: per configuration, the link pairs whose capsules
overlap and that no pair map proves apart (a table lookup before the pair's capsules), deepest first.

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
from robkin.compiled.collision.segments cimport segment_distance2
from robkin.compiled.chain.fk cimport BLOCK, Chain, finite_block, frame_poses, usable_layout
from robkin.compiled.runtime.threads cimport batch_threads

import numpy as np

cnp.import_array()

cdef enum:
    # blocks a thread must get before a batch is split (a block of 32 Panda configurations is ~10 us)
    MIN_BLOCKS_PER_THREAD = 8


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


cdef inline void bounding_radii(const double* caps, int C, double* S) noexcept nogil:
    """Each capsule's bounding sphere about its segment's midpoint: half the length plus the radius."""
    cdef int i
    cdef double x, y, z
    for i in range(C):
        x = caps[7 * i + 3] - caps[7 * i]
        y = caps[7 * i + 4] - caps[7 * i + 1]
        z = caps[7 * i + 5] - caps[7 * i + 2]
        S[i] = 0.5 * sqrt(x * x + y * y + z * z) + caps[7 * i + 6]


cdef inline bint spheres_apart(const double* W, const double* S, int u, int v) noexcept nogil:
    """Capsules u and v (ends in W, C x 6) are apart by their bounding spheres (radii S, about the segments'
    midpoints): then so are the capsules, with no segment distance needed."""
    cdef double x = W[6 * u] + W[6 * u + 3] - W[6 * v] - W[6 * v + 3]
    cdef double y = W[6 * u + 1] + W[6 * u + 4] - W[6 * v + 1] - W[6 * v + 4]
    cdef double z = W[6 * u + 2] + W[6 * u + 5] - W[6 * v + 2] - W[6 * v + 5]
    cdef double s = S[u] + S[v]
    return x * x + y * y + z * z > 4.0 * s * s


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
    cdef double rr, d2
    cdef int i
    if not finite_block(Q, n, N, j):
        return 1
    F = <double*>malloc(sizeof(double) * (16 * (n + 1) * m + 6 * C + C))
    if F == NULL:
        return -1
    W = F + 16 * (n + 1) * m
    S = W + 6 * C
    bounding_radii(caps, C, S)
    frame_poses(L, rev, n, Q + n * k0, m, F)
    for b in range(m):
        move_capsules(F + 16 * (n + 1) * b, n, caps, frame, C, W)
        if hit != NULL:
            hit[k0 + b] = 0
            for p in range(P):
                u = pairs[2 * p]
                v = pairs[2 * p + 1]
                if spheres_apart(W, S, u, v):
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


cdef int overlap_block(const double* L, const unsigned char* rev, int n, const double* Q, Py_ssize_t N,
                       Py_ssize_t j, const double* caps, const int* frame, int C, const int* pairs,
                       const int* link_of, int P, int LP, const int* map_of, const int* map_joints,
                       const double* map_lower, const double* map_width, const int* map_cells,
                       const Py_ssize_t* map_start,
                       const unsigned char* map_free, int* found, int* count) noexcept nogil:
    """Block j of ``overlaps``: per configuration k, count[k] link pairs whose capsules overlap and that no
    map clears, in found[k * LP ...], deepest overlap first. Returns as ``check_block``."""
    cdef Py_ssize_t k0 = BLOCK * j
    cdef int m = <int>(N - k0 if N - k0 < BLOCK else BLOCK), b, p, u, v, l, i, c, mp, i0, i1, jj, cells
    cdef double* F
    cdef double* W
    cdef double* S
    cdef double* D
    cdef double rr, d2, x, y, d
    cdef const double* q
    cdef bint inside
    if not finite_block(Q, n, N, j):
        return 1
    F = <double*>malloc(sizeof(double) * (16 * (n + 1) * m + 6 * C + C + LP))
    if F == NULL:
        return -1
    W = F + 16 * (n + 1) * m
    S = W + 6 * C
    D = S + C
    bounding_radii(caps, C, S)
    frame_poses(L, rev, n, Q + n * k0, m, F)
    for b in range(m):
        move_capsules(F + 16 * (n + 1) * b, n, caps, frame, C, W)
        q = Q + n * (k0 + b)
        for l in range(LP):
            D[l] = 1.0      # > 0: no overlap (yet)
            mp = map_of[l]
            if mp >= 0:     # the pair's map: the cell of its joints' values proven apart, or not
                cells = map_cells[mp]
                x = (q[map_joints[2 * mp]] - map_lower[2 * mp]) / map_width[2 * mp]
                inside = x >= 0.0 and x < cells
                i0 = <int>x if inside else 0
                jj = map_joints[2 * mp + 1]
                if jj >= 0 and inside:
                    y = (q[jj] - map_lower[2 * mp + 1]) / map_width[2 * mp + 1]
                    inside = y >= 0.0 and y < cells
                    i1 = <int>y if inside else 0
                    i0 = i0 * cells + i1
                if inside and (map_free[(map_start[mp] + i0) >> 3] >> ((map_start[mp] + i0) & 7)) & 1:
                    D[l] = 2.0      # cleared by its map: its capsules are not checked
        for p in range(P):
            l = link_of[p]
            if D[l] > 1.5:
                continue
            u = pairs[2 * p]
            v = pairs[2 * p + 1]
            if spheres_apart(W, S, u, v):
                continue
            rr = caps[7 * u + 6] + caps[7 * v + 6]
            d2 = segment_distance2(W + 6 * u, W + 6 * u + 3, W + 6 * v, W + 6 * v + 3)
            if d2 <= rr * rr:
                d = sqrt(d2) - rr
                if d > 0.0:     # touching to rounding (sqrt(d2) a hair above rr): an overlap of 0
                    d = 0.0
                if d < D[l]:
                    D[l] = d
        c = 0
        for l in range(LP):
            if D[l] > 0.0:
                continue
            # insert l, deepest (most negative D) first
            i = c
            while i > 0 and D[found[(k0 + b) * LP + i - 1]] > D[l]:
                found[(k0 + b) * LP + i] = found[(k0 + b) * LP + i - 1]
                i -= 1
            found[(k0 + b) * LP + i] = l
            c += 1
        count[k0 + b] = c
    free(F)
    return 0


cdef int check_overlap_args(const int* frame, int C, int n, const int* pairs, const int* link_of, int P, int LP,
                            const int* map_of, const int* mj, const double* ml, const double* mw,
                            const Py_ssize_t* ms, int M, const int* cells, Py_ssize_t nf) noexcept nogil:
    """0 when ``overlaps``' index arrays are consistent, else the number of its first problem (1: frames,
    2: pairs, 3: a link pair's map, 4: a map's joints, cells, widths or rows)."""
    cdef int k
    cdef Py_ssize_t size
    for k in range(C):
        if frame[k] < 0 or frame[k] > n:
            return 1
    for k in range(P):
        if pairs[2 * k] < 0 or pairs[2 * k] >= C or pairs[2 * k + 1] < 0 or pairs[2 * k + 1] >= C \
                or link_of[k] < 0 or link_of[k] >= LP:
            return 2
    for k in range(LP):
        if map_of[k] < -1 or map_of[k] >= M:
            return 3
    for k in range(M):
        if cells[k] < 1:
            return 4
        size = <Py_ssize_t>cells[k] * cells[k] if mj[2 * k + 1] >= 0 else cells[k]
        if mj[2 * k] < 0 or mj[2 * k] >= n or mj[2 * k + 1] < -1 or mj[2 * k + 1] >= n or ms[k] < 0 \
                or ms[k] + size > 8 * nf or not mw[2 * k] > 0.0 or not mw[2 * k + 1] > 0.0 \
                or not (ml[2 * k] - ml[2 * k] == 0.0) or not (ml[2 * k + 1] - ml[2 * k + 1] == 0.0):
            return 4
    return 0


def overlaps(Chain chain, q, caps, frame, pairs, link_of, link_pairs, map_of, map_joints, map_lower, map_width,
             map_cells, map_start, map_free, int threads=0):
    """int32 (Q, 3): the queries (row, link u, link v) a convex-parts test must still decide, for q (N, n):
    per configuration (rows in order) its link pairs whose capsules touch or overlap and that no pair map
    clears, deepest overlap first; a configuration without a row is free. None as ``collide``.

    Capsule pair p (``pairs`` (P, 2)) belongs to link pair ``link_of[p]`` of ``link_pairs`` (LP, 2).
    Maps: ``map_of`` (LP,) the map of each link pair (-1: none); map m tabulates joints ``map_joints[m]``
    (q indices, the second -1 for a map over one joint), cell x = (q_j - ``map_lower[m, i]``) /
    ``map_width[m, i]``, ``map_cells[m]`` per joint, and cell (i0, i1) is proven apart when bit
    ``map_start[m] + i0 * map_cells[m] + i1`` (one joint: ``+ i0``) of ``map_free`` (uint8, bit b of byte
    b >> 3 at place b & 7: ``np.packbits(..., bitorder="little")``) is set; a value outside
    [0, map_cells[m]) cells is not cleared."""
    cdef int n = chain.n
    cdef cnp.ndarray ca = np.ascontiguousarray(caps, dtype=np.float64)
    cdef cnp.ndarray fa = np.ascontiguousarray(frame, dtype=np.intc)
    cdef cnp.ndarray pa = np.ascontiguousarray(pairs, dtype=np.intc)
    cdef cnp.ndarray lo = np.ascontiguousarray(link_of, dtype=np.intc)
    cdef cnp.ndarray lp = np.ascontiguousarray(link_pairs, dtype=np.intc)
    cdef cnp.ndarray mo = np.ascontiguousarray(map_of, dtype=np.intc)
    cdef cnp.ndarray mj = np.ascontiguousarray(map_joints, dtype=np.intc).reshape(-1, 2)
    cdef cnp.ndarray ml = np.ascontiguousarray(map_lower, dtype=np.float64).reshape(-1, 2)
    cdef cnp.ndarray mw = np.ascontiguousarray(map_width, dtype=np.float64).reshape(-1, 2)
    cdef cnp.ndarray ms = np.ascontiguousarray(map_start, dtype=np.intp)
    cdef cnp.ndarray mc = np.ascontiguousarray(map_cells, dtype=np.intc).reshape(-1)
    cdef cnp.ndarray mf = np.ascontiguousarray(map_free, dtype=np.uint8).reshape(-1)
    cdef int C, P, LP, M, nt, status
    cdef Py_ssize_t N, j, blocks, bad = 0, oom = 0, total, k, t, r
    if ca.ndim != 2 or ca.shape[1] != 7 or fa.ndim != 1 or fa.shape[0] != ca.shape[0] or pa.ndim != 2 \
            or pa.shape[1] != 2 or lo.ndim != 1 or lo.shape[0] != pa.shape[0] or lp.ndim != 2 or lp.shape[1] != 2 \
            or mo.ndim != 1 or mo.shape[0] != lp.shape[0]:
        raise ValueError("overlaps: expected caps (C, 7), frame (C,), pairs (P, 2), link_of (P,), link_pairs (LP, 2), "
                         "map_of (LP,)")
    C = <int>ca.shape[0]
    P = <int>pa.shape[0]
    LP = <int>lp.shape[0]
    M = <int>mj.shape[0]
    if ml.shape[0] != M or mw.shape[0] != M or ms.shape[0] != M or mc.shape[0] != M:
        raise ValueError("overlaps: map arrays disagree in length")
    # the index checks as C loops (numpy's reductions would cost ~15 us a call: most of a small batch's time)
    cdef int problem = check_overlap_args(<const int*>cnp.PyArray_DATA(fa), C, n, <const int*>cnp.PyArray_DATA(pa),
                                          <const int*>cnp.PyArray_DATA(lo), P, LP, <const int*>cnp.PyArray_DATA(mo),
                                          <const int*>cnp.PyArray_DATA(mj), <const double*>cnp.PyArray_DATA(ml),
                                          <const double*>cnp.PyArray_DATA(mw),
                                          <const Py_ssize_t*>cnp.PyArray_DATA(ms), M,
                                          <const int*>cnp.PyArray_DATA(mc), mf.shape[0])
    if problem:
        raise ValueError((f"overlaps: frame indices must be in 0..{n}", "overlaps: pair indices out of range",
                          "overlaps: map arrays disagree in length",
                          "overlaps: map joints, cells or rows out of range")[problem - 1])
    if not usable_layout(q, n):
        return None
    N = cnp.PyArray_SIZE(q) // n
    cdef cnp.ndarray found_a = np.empty(N * max(LP, 1), dtype=np.intc)
    cdef cnp.ndarray count_a = np.zeros(N, dtype=np.intc)
    cdef const double* Q = <const double*>cnp.PyArray_DATA(q)
    cdef const double* Cp = <const double*>cnp.PyArray_DATA(ca)
    cdef const int* Fp = <const int*>cnp.PyArray_DATA(fa)
    cdef const int* Pp = <const int*>cnp.PyArray_DATA(pa)
    cdef const int* Lo = <const int*>cnp.PyArray_DATA(lo)
    cdef const int* Lk = <const int*>cnp.PyArray_DATA(lp)
    cdef const int* Mo = <const int*>cnp.PyArray_DATA(mo)
    cdef const int* Mj = <const int*>cnp.PyArray_DATA(mj)
    cdef const double* Ml = <const double*>cnp.PyArray_DATA(ml)
    cdef const double* Mw = <const double*>cnp.PyArray_DATA(mw)
    cdef const Py_ssize_t* Ms = <const Py_ssize_t*>cnp.PyArray_DATA(ms)
    cdef const int* Mc = <const int*>cnp.PyArray_DATA(mc)
    cdef const unsigned char* Mf = <const unsigned char*>cnp.PyArray_DATA(mf)
    cdef int* Fd = <int*>cnp.PyArray_DATA(found_a)
    cdef int* Ct = <int*>cnp.PyArray_DATA(count_a)
    blocks = (N + BLOCK - 1) // BLOCK
    with nogil:
        nt = batch_threads(threads, blocks, MIN_BLOCKS_PER_THREAD) if blocks > 1 else 1
        if nt > 1:
            for j in prange(blocks, num_threads=nt, schedule="dynamic", chunksize=2):
                status = overlap_block(chain.L, chain.rev, n, Q, N, j, Cp, Fp, C, Pp, Lo, P, LP, Mo, Mj, Ml, Mw,
                                       Mc, Ms, Mf, Fd, Ct)
                if status > 0:
                    bad += 1
                elif status < 0:
                    oom += 1
        else:
            for j in range(blocks):
                status = overlap_block(chain.L, chain.rev, n, Q, N, j, Cp, Fp, C, Pp, Lo, P, LP, Mo, Mj, Ml, Mw,
                                       Mc, Ms, Mf, Fd, Ct)
                if status > 0:
                    bad += 1
                    break
                elif status < 0:
                    oom += 1
                    break
    if oom:
        raise MemoryError("overlaps: no memory for a block of frames")
    if bad:
        return None
    total = 0
    for k in range(N):
        total += Ct[k]
    cdef cnp.ndarray out = np.empty((total, 3), dtype=np.intc)
    cdef int* O = <int*>cnp.PyArray_DATA(out)
    r = 0
    for k in range(N):
        for t in range(Ct[k]):
            O[3 * r] = <int>k
            O[3 * r + 1] = Lk[2 * Fd[k * LP + t]]
            O[3 * r + 2] = Lk[2 * Fd[k * LP + t] + 1]
            r += 1
    return out
