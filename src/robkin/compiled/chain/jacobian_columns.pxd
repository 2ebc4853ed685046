# cython: language_level=3
"""A block's Jacobian columns from its walk (``fk.walk_block`` with Z): the step after the walk, shared by
the single-configuration path (``jacobian.pyx``) and the batch block kernels (``kernel_bodies.pxi``,
compiled portable and for AVX2)."""

from robkin.compiled.chain.fk cimport BLOCK


cdef inline void finish_block(const unsigned char* rev, int n, int kind, const double* P, const double* Z,
                              int ld, int m, double* J) noexcept nogil:
    """J (m x 6 x n) from the parked p_i, z_i (Z, see ``fk.walk_block``) and the tool poses P of a block.

    Column i of every configuration b of the block is computed in loops over b that vectorise (joint type
    and kind are the same for the whole block), into W, V, then written to J. Z may be J itself when
    m = 1 (a column is read before it is written).
    """
    cdef double W[3 * BLOCK]
    cdef double V[3 * BLOCK]
    cdef double z0, z1, z2, d0, d1, d2
    cdef const double* p0
    cdef const double* p1
    cdef const double* p2
    cdef const double* zi0
    cdef const double* zi1
    cdef const double* zi2
    cdef double* Jb
    cdef int i, b, r, top = 0 if kind == 0 else 3      # the rows of v: [v; w] (geometric), (w, v) otherwise
    for i in range(n):
        p0 = Z + ld * i
        p1 = Z + ld * (n + i)
        p2 = Z + ld * (2 * n + i)
        zi0 = Z + ld * (3 * n + i)
        zi1 = Z + ld * (4 * n + i)
        zi2 = Z + ld * (5 * n + i)
        if not rev[i]:
            # prismatic: no rotation, the axis is the velocity
            for b in range(m):
                W[b] = 0.0
                W[BLOCK + b] = 0.0
                W[2 * BLOCK + b] = 0.0
                V[b] = zi0[b]
                V[BLOCK + b] = zi1[b]
                V[2 * BLOCK + b] = zi2[b]
        elif kind == 1:
            # space: w = z, v = -z x p = p x z
            for b in range(m):
                z0 = zi0[b]
                z1 = zi1[b]
                z2 = zi2[b]
                W[b] = z0
                W[BLOCK + b] = z1
                W[2 * BLOCK + b] = z2
                V[b] = p1[b] * z2 - p2[b] * z1
                V[BLOCK + b] = p2[b] * z0 - p0[b] * z2
                V[2 * BLOCK + b] = p0[b] * z1 - p1[b] * z0
        else:
            # geometric and body: w = z, v = z x (p_tool - p)
            for b in range(m):
                z0 = zi0[b]
                z1 = zi1[b]
                z2 = zi2[b]
                d0 = P[BLOCK * 3 + b] - p0[b]
                d1 = P[BLOCK * 7 + b] - p1[b]
                d2 = P[BLOCK * 11 + b] - p2[b]
                W[b] = z0
                W[BLOCK + b] = z1
                W[2 * BLOCK + b] = z2
                V[b] = z1 * d2 - z2 * d1
                V[BLOCK + b] = z2 * d0 - z0 * d2
                V[2 * BLOCK + b] = z0 * d1 - z1 * d0
        if kind == 2:
            # body: both halves seen from the tool frame, R^T w and R^T v (v = z x (p_tool - p) is
            # the space v minus p_tool x w, as Ad_{T^-1} prescribes)
            rotate_back(P, W, m)
            rotate_back(P, V, m)
        for b in range(m):
            Jb = J + 6 * n * b + i
            for r in range(3):
                Jb[n * (top + r)] = V[BLOCK * r + b]
                Jb[n * (3 - top + r)] = W[BLOCK * r + b]


cdef inline void rotate_back(const double* P, double* X, int m) noexcept nogil:
    """X[:, b] <- R_b^T X[:, b] for the tool rotations R_b of the SoA block P (X: 3 x BLOCK)."""
    cdef double x0, x1, x2
    cdef int b
    for b in range(m):
        x0 = X[b]
        x1 = X[BLOCK + b]
        x2 = X[2 * BLOCK + b]
        X[b] = P[b] * x0 + P[BLOCK * 4 + b] * x1 + P[BLOCK * 8 + b] * x2
        X[BLOCK + b] = P[BLOCK + b] * x0 + P[BLOCK * 5 + b] * x1 + P[BLOCK * 9 + b] * x2
        X[2 * BLOCK + b] = P[BLOCK * 2 + b] * x0 + P[BLOCK * 6 + b] * x1 + P[BLOCK * 10 + b] * x2
