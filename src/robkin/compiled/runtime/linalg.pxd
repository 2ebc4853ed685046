# cython: language_level=3
"""Small fixed-size linear algebra shared by every compiled kernel (``cimport`` it, nothing to import).

Conventions: plain C arrays of doubles, row-major. A 3-vector is ``double[3]``, a rotation ``double[9]``
(``R[3*i + j]``), a pose ``double[16]`` (``T[4*i + j]``, last row 0 0 0 1). Twists are ordered (w, v).
Outputs never alias inputs unless a function says so. Everything is ``nogil`` and allocation-free.

Append new helpers at the END of this file; existing signatures are shared with other modules and stay
as they are.
"""

from libc.math cimport sqrt, sin, cos, atan2, fabs


cdef inline double dot3(const double* a, const double* b) noexcept nogil:
    """a . b"""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


cdef inline double norm3(const double* a) noexcept nogil:
    """|a|"""
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


cdef inline void cross3(const double* a, const double* b, double* out) noexcept nogil:
    """out = a x b (out must not alias a or b)."""
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


cdef inline void mat3_mul(const double* A, const double* B, double* out) noexcept nogil:
    """out = A B for 3x3 row-major matrices."""
    cdef int i
    for i in range(3):
        out[3 * i + 0] = A[3 * i] * B[0] + A[3 * i + 1] * B[3] + A[3 * i + 2] * B[6]
        out[3 * i + 1] = A[3 * i] * B[1] + A[3 * i + 1] * B[4] + A[3 * i + 2] * B[7]
        out[3 * i + 2] = A[3 * i] * B[2] + A[3 * i + 1] * B[5] + A[3 * i + 2] * B[8]


cdef inline void mat3_vec(const double* A, const double* v, double* out) noexcept nogil:
    """out = A v for a 3x3 row-major A."""
    out[0] = A[0] * v[0] + A[1] * v[1] + A[2] * v[2]
    out[1] = A[3] * v[0] + A[4] * v[1] + A[5] * v[2]
    out[2] = A[6] * v[0] + A[7] * v[1] + A[8] * v[2]


cdef inline void mat3T_vec(const double* A, const double* v, double* out) noexcept nogil:
    """out = A^T v for a 3x3 row-major A."""
    out[0] = A[0] * v[0] + A[3] * v[1] + A[6] * v[2]
    out[1] = A[1] * v[0] + A[4] * v[1] + A[7] * v[2]
    out[2] = A[2] * v[0] + A[5] * v[1] + A[8] * v[2]


cdef inline void tf_rot(const double* T, double* R) noexcept nogil:
    """R = rotation block (3x3 row-major) of the pose T."""
    cdef int i
    for i in range(3):
        R[3 * i + 0] = T[4 * i + 0]
        R[3 * i + 1] = T[4 * i + 1]
        R[3 * i + 2] = T[4 * i + 2]


cdef inline void tf_identity(double* T) noexcept nogil:
    """T = I (4x4)."""
    cdef int i
    for i in range(16):
        T[i] = 0.0
    T[0] = 1.0
    T[5] = 1.0
    T[10] = 1.0
    T[15] = 1.0


cdef inline void tf_copy(const double* A, double* out) noexcept nogil:
    """out = A (4x4)."""
    cdef int i
    for i in range(16):
        out[i] = A[i]


cdef inline void tf_mul(const double* A, const double* B, double* out) noexcept nogil:
    """out = A B for rigid transforms (last rows taken to be 0 0 0 1; out's last row is written so)."""
    cdef int i
    for i in range(3):
        out[4 * i + 0] = A[4 * i] * B[0] + A[4 * i + 1] * B[4] + A[4 * i + 2] * B[8]
        out[4 * i + 1] = A[4 * i] * B[1] + A[4 * i + 1] * B[5] + A[4 * i + 2] * B[9]
        out[4 * i + 2] = A[4 * i] * B[2] + A[4 * i + 1] * B[6] + A[4 * i + 2] * B[10]
        out[4 * i + 3] = (A[4 * i] * B[3] + A[4 * i + 1] * B[7] + A[4 * i + 2] * B[11]
                          + A[4 * i + 3])
    out[12] = 0.0
    out[13] = 0.0
    out[14] = 0.0
    out[15] = 1.0


cdef inline void tf_inv(const double* T, double* out) noexcept nogil:
    """out = T^-1 for a rigid transform: (R^T, -R^T p)."""
    cdef int i
    for i in range(3):
        out[4 * i + 0] = T[i]
        out[4 * i + 1] = T[4 + i]
        out[4 * i + 2] = T[8 + i]
        out[4 * i + 3] = -(T[i] * T[3] + T[4 + i] * T[7] + T[8 + i] * T[11])
    out[12] = 0.0
    out[13] = 0.0
    out[14] = 0.0
    out[15] = 1.0


cdef inline void rodrigues(const double* axis, double angle, double* R) noexcept nogil:
    """R = exp([axis] angle) (3x3 row-major) for a UNIT axis (Rodrigues' formula)."""
    cdef double s = sin(angle)
    cdef double c = cos(angle)
    cdef double t = 1.0 - c
    cdef double x = axis[0], y = axis[1], z = axis[2]
    R[0] = c + t * x * x
    R[1] = t * x * y - s * z
    R[2] = t * x * z + s * y
    R[3] = t * x * y + s * z
    R[4] = c + t * y * y
    R[5] = t * y * z - s * x
    R[6] = t * x * z - s * y
    R[7] = t * y * z + s * x
    R[8] = c + t * z * z


cdef inline void rot_log(const double* R, double* w) noexcept nogil:
    """w = log(R) as a rotation vector (axis * angle, angle in [0, pi]) of a 3x3 row-major rotation.

    The angle comes from atan2(|sin|, cos), accurate at every angle (acos of the trace loses half the
    digits near 0 and pi). Away from pi the axis is the skew part / (2 sin); near pi, where the skew
    part vanishes, the axis is read from the largest diagonal entry of (R + I) / 2 = a a^T (+ the sign
    of the skew part), which is well conditioned there.
    """
    cdef double sx = R[7] - R[5]
    cdef double sy = R[2] - R[6]
    cdef double sz = R[3] - R[1]
    cdef double s2 = sqrt(sx * sx + sy * sy + sz * sz)       # 2 |sin(theta)|
    cdef double c2 = R[0] + R[4] + R[8] - 1.0                 # 2 cos(theta)
    cdef double theta = atan2(s2, c2)
    cdef double k, ax, ay, az, n
    # Below theta ~ 1e-8 theta / (2 sin theta) = 1/2 to rounding (the next term is theta^2 / 12).
    if theta < 1e-8:
        w[0] = 0.5 * sx
        w[1] = 0.5 * sy
        w[2] = 0.5 * sz
        return
    # Up to pi - 1e-3 the skew part is at least ~2e-3 in size, so dividing by it keeps ~13 digits;
    # closer to pi the symmetric part gives the axis more accurately.
    if theta < 3.14059265358979:
        k = theta / s2
        w[0] = k * sx
        w[1] = k * sy
        w[2] = k * sz
        return
    # Near pi the symmetric part is cos I + (1 - cos) a a^T: the largest diagonal entry gives one
    # component, the off-diagonal sums the other two, the skew part the overall sign.
    c2 = 0.5 * c2                                             # cos(theta)
    k = 1.0 - c2                                              # in (1.999, 2]: no cancellation
    if R[0] >= R[4] and R[0] >= R[8]:
        ax = sqrt(fabs((R[0] - c2) / k))
        ay = 0.5 * (R[1] + R[3]) / (k * ax)
        az = 0.5 * (R[2] + R[6]) / (k * ax)
        if sx < 0.0:
            ax, ay, az = -ax, -ay, -az
    elif R[4] >= R[8]:
        ay = sqrt(fabs((R[4] - c2) / k))
        ax = 0.5 * (R[1] + R[3]) / (k * ay)
        az = 0.5 * (R[5] + R[7]) / (k * ay)
        if sy < 0.0:
            ax, ay, az = -ax, -ay, -az
    else:
        az = sqrt(fabs((R[8] - c2) / k))
        ax = 0.5 * (R[2] + R[6]) / (k * az)
        ay = 0.5 * (R[5] + R[7]) / (k * az)
        if sz < 0.0:
            ax, ay, az = -ax, -ay, -az
    n = sqrt(ax * ax + ay * ay + az * az)
    w[0] = theta * ax / n
    w[1] = theta * ay / n
    w[2] = theta * az / n


cdef inline void exp_screw(const double* S, double q, double* T) noexcept nogil:
    """T = exp([S] q) (4x4) of a unit screw S = (w, v): |w| = 1 (revolute) or w = 0, |v| = 1 (prismatic).

    Rotation by Rodrigues, translation G(q) v with G = I q + (1 - cos q) [w] + (q - sin q) [w]^2
    (Modern Robotics eq. 3.88); for w = 0 this is the translation v q.
    """
    cdef double wx = S[0], wy = S[1], wz = S[2]
    cdef double vx = S[3], vy = S[4], vz = S[5]
    cdef double s, c, t, u, wxv0, wxv1, wxv2, wv
    if wx == 0.0 and wy == 0.0 and wz == 0.0:
        tf_identity(T)
        T[3] = vx * q
        T[7] = vy * q
        T[11] = vz * q
        return
    s = sin(q)
    c = cos(q)
    t = 1.0 - c
    T[0] = c + t * wx * wx
    T[1] = t * wx * wy - s * wz
    T[2] = t * wx * wz + s * wy
    T[4] = t * wx * wy + s * wz
    T[5] = c + t * wy * wy
    T[6] = t * wy * wz - s * wx
    T[8] = t * wx * wz - s * wy
    T[9] = t * wy * wz + s * wx
    T[10] = c + t * wz * wz
    # [w] v = w x v; [w]^2 v = w (w . v) - v for unit w
    wxv0 = wy * vz - wz * vy
    wxv1 = wz * vx - wx * vz
    wxv2 = wx * vy - wy * vx
    wv = wx * vx + wy * vy + wz * vz
    u = q - s
    T[3] = q * vx + t * wxv0 + u * (wx * wv - vx)
    T[7] = q * vy + t * wxv1 + u * (wy * wv - vy)
    T[11] = q * vz + t * wxv2 + u * (wz * wv - vz)
    T[12] = 0.0
    T[13] = 0.0
    T[14] = 0.0
    T[15] = 1.0


cdef inline double tall_volume(double* M, int m, int k) noexcept nogil:
    """Product of the k singular values of a tall M (m x k row-major, m >= k); M is overwritten.

    Householder QR: the product is |det R| = prod |R_jj|, computed stably (no Gram matrix, whose
    determinant would lose half the digits near a singularity).
    """
    cdef int i, j, c
    cdef double nx, alpha, vnorm2, s, vol = 1.0
    for j in range(k):
        nx = 0.0
        for i in range(j, m):
            nx += M[i * k + j] * M[i * k + j]
        nx = sqrt(nx)
        if nx == 0.0:
            return 0.0
        alpha = -nx if M[j * k + j] >= 0.0 else nx
        vol *= nx
        # v = x - alpha e1 stored in column j (rows j..m-1); |v|^2 = 2 nx (nx + |x_0|)
        M[j * k + j] -= alpha
        vnorm2 = 2.0 * nx * (nx + fabs(M[j * k + j] + alpha))
        for c in range(j + 1, k):
            s = 0.0
            for i in range(j, m):
                s += M[i * k + j] * M[i * k + c]
            s = 2.0 * s / vnorm2
            for i in range(j, m):
                M[i * k + c] -= s * M[i * k + j]
    return vol
