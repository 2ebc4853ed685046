# cython: language_level=3
"""Rigid-body dynamics of a serial chain: recursive Newton-Euler and the composite-rigid-body mass matrix.

``ChainDynamics`` holds a robot's fixed transforms (the same L as ``fk.Chain``: T(q) = L_1 Z_1(q_1) ...
L_n Z_n(q_n) L_{n+1}) and, per moving body i, its mass, centre of mass and inertia about that centre,
expressed in the body's own frame F_i(q) = L_1 Z_1 ... L_i Z_i (the GJD frame J_i moved to q, whose z
axis is joint i's axis through its origin). Everything is done in body frames with 3-vectors (Craig's
formulation of Luh-Walker-Paul's recursion; Featherstone's CRBA with the spatial inertia kept as mass,
centre and rotational inertia), one configuration at a time; a batch is a loop of single
configurations, so a batch and the single calls agree bit for bit.

The methods validate only what keeps them memory safe: they return ``None`` unless q, qd, qdd are
C-contiguous float64 arrays of one shape (n,) or (N, n) with finite entries; the Python layer
(``robkin.dynamics.rigid_body``) validates and explains.
"""

cimport numpy as cnp
from libc.stdlib cimport malloc, free
from robkin.compiled.fk cimport usable_q
from robkin.compiled.sincos cimport rk_sincos_one

import numpy as np

cnp.import_array()


cdef inline void cross(const double* a, const double* b, double* out) noexcept nogil:
    cdef double x = a[1] * b[2] - a[2] * b[1]
    cdef double y = a[2] * b[0] - a[0] * b[2]
    cdef double z = a[0] * b[1] - a[1] * b[0]
    out[0] = x
    out[1] = y
    out[2] = z


cdef inline void mat_vec(const double* R, const double* v, double* out) noexcept nogil:
    """out = R v (R row-major 3x3); out may not alias v."""
    out[0] = R[0] * v[0] + R[1] * v[1] + R[2] * v[2]
    out[1] = R[3] * v[0] + R[4] * v[1] + R[5] * v[2]
    out[2] = R[6] * v[0] + R[7] * v[1] + R[8] * v[2]


cdef inline void mat_t_vec(const double* R, const double* v, double* out) noexcept nogil:
    """out = R^T v; out may not alias v."""
    out[0] = R[0] * v[0] + R[3] * v[1] + R[6] * v[2]
    out[1] = R[1] * v[0] + R[4] * v[1] + R[7] * v[2]
    out[2] = R[2] * v[0] + R[5] * v[1] + R[8] * v[2]


cdef inline void joint_transform(const double* L, bint revolute, double q, double* R, double* p) noexcept nogil:
    """Parent -> child transform X = L Z(q) as rotation R (row-major) and translation p.

    L is a 4x4 row-major matrix; Z(q) rotates about (revolute) or translates along (prismatic) z."""
    cdef double s, c
    cdef int r
    if revolute:
        rk_sincos_one(q, &s, &c)
        for r in range(3):
            R[3 * r] = L[4 * r] * c + L[4 * r + 1] * s
            R[3 * r + 1] = L[4 * r + 1] * c - L[4 * r] * s
            R[3 * r + 2] = L[4 * r + 2]
            p[r] = L[4 * r + 3]
    else:
        for r in range(3):
            R[3 * r] = L[4 * r]
            R[3 * r + 1] = L[4 * r + 1]
            R[3 * r + 2] = L[4 * r + 2]
            p[r] = L[4 * r + 3] + L[4 * r + 2] * q


cdef struct Work:
    double* R      # (n, 9) parent -> child rotations at q
    double* p      # (n, 3) parent -> child translations at q
    double* w      # (n, 3) angular velocity of body i, frame i
    double* dw     # (n, 3) angular acceleration
    double* a      # (n, 3) linear acceleration of frame i's origin (gravity included as -g)
    double* F      # (n, 3) force on body i at its centre (frame i)
    double* T      # (n, 3) moment on body i about its centre (frame i)
    double* cm     # (n,) composite masses
    double* cc     # (n, 3) composite centres (frame i)
    double* cI     # (n, 9) composite inertias about their centres (frame i axes)


cdef int work_alloc(Work* W, int n) noexcept nogil:
    cdef double* block = <double*>malloc(sizeof(double) * n * (9 + 3 * 6 + 1 + 3 + 9))
    if block == NULL:
        return -1
    W.R = block
    W.p = W.R + 9 * n
    W.w = W.p + 3 * n
    W.dw = W.w + 3 * n
    W.a = W.dw + 3 * n
    W.F = W.a + 3 * n
    W.T = W.F + 3 * n
    W.cm = W.T + 3 * n
    W.cc = W.cm + n
    W.cI = W.cc + 3 * n
    return 0


cdef void rnea_one(const double* L, const unsigned char* rev, int n, const double* mass, const double* com,
                   const double* inertia, const double* q, const double* qd, const double* qdd,
                   const double* g, Work* W, double* tau) noexcept nogil:
    """Joint torques/forces tau (n,) for one configuration. qd and qdd may be NULL (zero)."""
    cdef int i, k
    cdef double wp[3]
    cdef double dwp[3]
    cdef double ap[3]
    cdef double t[3]
    cdef double u[3]
    cdef double f[3]
    cdef double m[3]
    cdef double fc[3]
    cdef double mc[3]
    cdef double vq, aq
    cdef double* R
    cdef double* p
    cdef double* w
    cdef double* dw
    cdef double* a
    cdef const double* c
    cdef const double* I
    wp[0] = 0.0; wp[1] = 0.0; wp[2] = 0.0
    dwp[0] = 0.0; dwp[1] = 0.0; dwp[2] = 0.0
    ap[0] = -g[0]; ap[1] = -g[1]; ap[2] = -g[2]   # a fictitious upward acceleration stands for gravity
    for i in range(n):
        R = W.R + 9 * i
        p = W.p + 3 * i
        w = W.w + 3 * i
        dw = W.dw + 3 * i
        a = W.a + 3 * i
        joint_transform(L + 16 * i, rev[i], q[i], R, p)
        vq = 0.0 if qd == NULL else qd[i]
        aq = 0.0 if qdd == NULL else qdd[i]
        # acceleration of this frame's origin, in the parent frame: a_p + dw_p x p + w_p x (w_p x p)
        cross(dwp, p, t)
        cross(wp, p, u)
        cross(wp, u, m)
        for k in range(3):
            t[k] = ap[k] + t[k] + m[k]
        mat_t_vec(R, t, a)
        mat_t_vec(R, wp, w)
        mat_t_vec(R, dwp, dw)
        if rev[i]:
            # dw += w_parent x (z qd) before w gets its own z qd
            dw[0] += w[1] * vq
            dw[1] -= w[0] * vq
            dw[2] += aq
            w[2] += vq
        else:
            # Coriolis 2 w x (z qd) and the joint's own acceleration z qdd
            a[0] += 2.0 * w[1] * vq
            a[1] -= 2.0 * w[0] * vq
            a[2] += aq
        for k in range(3):
            wp[k] = w[k]
            dwp[k] = dw[k]
            ap[k] = a[k]
        # force and moment on the body at its centre of mass
        c = com + 3 * i
        I = inertia + 9 * i
        cross(dw, c, t)
        cross(w, c, u)
        cross(w, u, m)
        for k in range(3):
            W.F[3 * i + k] = mass[i] * (a[k] + t[k] + m[k])
        mat_vec(I, w, u)
        cross(w, u, t)
        mat_vec(I, dw, u)
        for k in range(3):
            W.T[3 * i + k] = u[k] + t[k]
    # backward: force f and moment m (about frame i's origin) that body i-1 exerts on body i
    f[0] = 0.0; f[1] = 0.0; f[2] = 0.0
    m[0] = 0.0; m[1] = 0.0; m[2] = 0.0
    for i in range(n - 1, -1, -1):
        if i < n - 1:
            R = W.R + 9 * (i + 1)
            p = W.p + 3 * (i + 1)
            mat_vec(R, f, fc)
            mat_vec(R, m, mc)
            cross(p, fc, t)
            for k in range(3):
                mc[k] += t[k]
        else:
            fc[0] = 0.0; fc[1] = 0.0; fc[2] = 0.0
            mc[0] = 0.0; mc[1] = 0.0; mc[2] = 0.0
        cross(com + 3 * i, W.F + 3 * i, t)
        for k in range(3):
            f[k] = W.F[3 * i + k] + fc[k]
            m[k] = W.T[3 * i + k] + t[k] + mc[k]
        tau[i] = m[2] if rev[i] else f[2]


cdef void crba_one(const double* L, const unsigned char* rev, int n, const double* mass, const double* com,
                   const double* inertia, const double* q, Work* W, double* M) noexcept nogil:
    """Joint-space mass matrix M (n, n), row-major, for one configuration."""
    cdef int i, j, k, r
    cdef double mt, mc, d2
    cdef double cp[3]
    cdef double tmp[9]
    cdef double Ir[9]
    cdef double d1[3]
    cdef double d[3]
    cdef double f[3]
    cdef double nm[3]
    cdef double t[3]
    cdef double u[3]
    cdef double* R
    cdef double* p
    cdef double* C
    cdef double* IC
    for i in range(n):
        joint_transform(L + 16 * i, rev[i], q[i], W.R + 9 * i, W.p + 3 * i)
    # composite bodies, tip to base: body i plus everything beyond it, in frame i
    for i in range(n - 1, -1, -1):
        C = W.cc + 3 * i
        IC = W.cI + 9 * i
        W.cm[i] = mass[i]
        for k in range(3):
            C[k] = com[3 * i + k]
        for k in range(9):
            IC[k] = inertia[9 * i + k]
        if i == n - 1:
            continue
        mc = W.cm[i + 1]
        if mc == 0.0:
            continue
        R = W.R + 9 * (i + 1)
        p = W.p + 3 * (i + 1)
        mat_vec(R, W.cc + 3 * (i + 1), cp)
        for k in range(3):
            cp[k] += p[k]
        # child's inertia in this frame's axes: R I R^T
        for r in range(3):
            for k in range(3):
                tmp[3 * r + k] = (W.cI[9 * (i + 1) + 3 * r] * R[3 * k] + W.cI[9 * (i + 1) + 3 * r + 1] * R[3 * k + 1]
                                  + W.cI[9 * (i + 1) + 3 * r + 2] * R[3 * k + 2])
        for r in range(3):
            for k in range(3):
                Ir[3 * r + k] = R[3 * r] * tmp[k] + R[3 * r + 1] * tmp[3 + k] + R[3 * r + 2] * tmp[6 + k]
        mt = W.cm[i] + mc
        for k in range(3):
            t[k] = (W.cm[i] * C[k] + mc * cp[k]) / mt
            d1[k] = C[k] - t[k]
            d[k] = cp[k] - t[k]
        # parallel axis for both parts about the new centre t
        for r in range(3):
            for k in range(3):
                IC[3 * r + k] += Ir[3 * r + k] - W.cm[i] * d1[r] * d1[k] - mc * d[r] * d[k]
        d2 = W.cm[i] * (d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]) + mc * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        IC[0] += d2
        IC[4] += d2
        IC[8] += d2
        W.cm[i] = mt
        for k in range(3):
            C[k] = t[k]
    # column i: the force that a unit motion of joint i asks of composite body i, carried to the base
    for i in range(n):
        mt = W.cm[i]
        C = W.cc + 3 * i
        IC = W.cI + 9 * i
        if rev[i]:
            # w = z, v_origin = 0: f = m (z x c), moment about the origin = I_c z + m c x (z x c)
            f[0] = -mt * C[1]
            f[1] = mt * C[0]
            f[2] = 0.0
            cross(C, f, t)
            for k in range(3):
                nm[k] = IC[3 * k + 2] + t[k]
        else:
            # w = 0, v = z: f = m z, moment about the origin = c x f
            f[0] = 0.0
            f[1] = 0.0
            f[2] = mt
            cross(C, f, nm)
        M[i * n + i] = nm[2] if rev[i] else f[2]
        for j in range(i - 1, -1, -1):
            R = W.R + 9 * (j + 1)
            p = W.p + 3 * (j + 1)
            mat_vec(R, f, u)
            mat_vec(R, nm, t)
            cross(p, u, nm)
            for k in range(3):
                f[k] = u[k]
                nm[k] += t[k]
            M[j * n + i] = nm[2] if rev[j] else f[2]
            M[i * n + j] = M[j * n + i]


cdef class ChainDynamics:
    """A chain's fixed transforms, joint types and body mass properties, for the dynamics kernels.

    Parameters
    ----------
    L : (n+1, 4, 4) float array
        The fixed transforms of ``fk.Chain``.
    revolute : (n,) bool array
    mass : (n,) float array
        Mass of bodies 1..n (kg).
    com : (n, 3) float array
        Centre of mass of body i in its frame F_i (m).
    inertia : (n, 3, 3) float array
        Inertia of body i about its centre of mass in F_i's axes (kg m^2).
    """

    cdef readonly int n
    cdef object _owners
    cdef const double* L
    cdef const unsigned char* rev
    cdef const double* mass
    cdef const double* com
    cdef const double* inertia

    def __cinit__(self, L, revolute, mass, com, inertia):
        cdef cnp.ndarray La = np.ascontiguousarray(L, dtype=np.float64)
        cdef cnp.ndarray ra = np.ascontiguousarray(revolute, dtype=np.uint8)
        cdef cnp.ndarray ma = np.ascontiguousarray(mass, dtype=np.float64)
        cdef cnp.ndarray ca = np.ascontiguousarray(com, dtype=np.float64)
        cdef cnp.ndarray Ia = np.ascontiguousarray(inertia, dtype=np.float64)
        n = ra.shape[0]
        if (n < 1 or La.ndim != 3 or La.shape[0] != n + 1 or La.shape[1] != 4 or La.shape[2] != 4
                or ma.ndim != 1 or ma.shape[0] != n or ca.ndim != 2 or ca.shape[0] != n or ca.shape[1] != 3
                or Ia.ndim != 3 or Ia.shape[0] != n or Ia.shape[1] != 3 or Ia.shape[2] != 3):
            raise ValueError("ChainDynamics: expected L (n+1, 4, 4), revolute (n,), mass (n,), com (n, 3), "
                             "inertia (n, 3, 3)")
        self.n = n
        self._owners = (La, ra, ma, ca, Ia)
        self.L = <const double*>cnp.PyArray_DATA(La)
        self.rev = <const unsigned char*>cnp.PyArray_DATA(ra)
        self.mass = <const double*>cnp.PyArray_DATA(ma)
        self.com = <const double*>cnp.PyArray_DATA(ca)
        self.inertia = <const double*>cnp.PyArray_DATA(Ia)

    def inverse_dynamics(self, q, qd, qdd, gravity):
        """Joint torques/forces (n,) or (N, n) for q, qd, qdd of one shape (qd, qdd may be None: zero),
        gravity (3,) in the base frame; None if an array is not usable as is."""
        cdef Py_ssize_t N, k
        cdef const double* Q
        cdef const double* QD = NULL
        cdef const double* QDD = NULL
        cdef double* O
        cdef double g[3]
        cdef Work W
        cdef int n = self.n, failed = 0
        if not usable_q(q, n):
            return None
        for other in (qd, qdd):
            if other is not None and (not usable_q(other, n) or other.shape != q.shape):
                return None
        ga = np.ascontiguousarray(gravity, dtype=np.float64)
        if ga.shape != (3,):
            return None
        g[0] = ga[0]; g[1] = ga[1]; g[2] = ga[2]
        out = np.empty(q.shape, dtype=np.float64)
        Q = <const double*>cnp.PyArray_DATA(q)
        if qd is not None:
            QD = <const double*>cnp.PyArray_DATA(qd)
        if qdd is not None:
            QDD = <const double*>cnp.PyArray_DATA(qdd)
        O = <double*>cnp.PyArray_DATA(out)
        N = cnp.PyArray_SIZE(q) // n
        with nogil:
            if work_alloc(&W, n) != 0:
                failed = 1
            else:
                for k in range(N):
                    rnea_one(self.L, self.rev, n, self.mass, self.com, self.inertia, Q + k * n,
                             QD + k * n if QD != NULL else QD, QDD + k * n if QDD != NULL else QDD, g, &W, O + k * n)
                free(W.R)
        if failed:
            raise MemoryError()
        return out

    def mass_matrix(self, q):
        """Mass matrix (n, n) for q (n,), (N, n, n) for q (N, n); None if q is not usable as is."""
        cdef Py_ssize_t N, k
        cdef const double* Q
        cdef double* O
        cdef Work W
        cdef int n = self.n, failed = 0
        if not usable_q(q, n):
            return None
        out = np.empty(q.shape + (n,), dtype=np.float64)
        Q = <const double*>cnp.PyArray_DATA(q)
        O = <double*>cnp.PyArray_DATA(out)
        N = cnp.PyArray_SIZE(q) // n
        with nogil:
            if work_alloc(&W, n) != 0:
                failed = 1
            else:
                for k in range(N):
                    crba_one(self.L, self.rev, n, self.mass, self.com, self.inertia, Q + k * n, &W, O + k * n * n)
                free(W.R)
        if failed:
            raise MemoryError()
        return out
