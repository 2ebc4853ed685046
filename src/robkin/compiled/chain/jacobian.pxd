# cython: language_level=3
"""Jacobian kernel shared with the Levenberg-Marquardt solver (``lm.pyx``)."""

cdef void jacobian_one(const double* L, const unsigned char* rev, int n, const double* q, int kind,
                       double* J, double* T) noexcept nogil
