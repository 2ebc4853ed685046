# cython: language_level=3
"""The distance between two segments, shared by the capsule kernels (``capsules.pyx``, ``parts.pyx``)."""

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
