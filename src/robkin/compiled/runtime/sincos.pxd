# cython: language_level=3
"""sin and cos of an array of angles in one vectorisable pass (``sincos.h``), for the compiled kernels.

Every FK, frames and Jacobian kernel takes its joints' sines and cosines from here, one configuration or
many, so a batch and a single call agree bit for bit. Accuracy: within 1 ulp of glibc's sin and cos.
"""

cdef extern from "runtime/sincos.h" nogil:
    const double RK_SINCOS_BOUND
    void rk_sincos_array(const double* x, double* s, double* c, int m)
    void rk_sincos_one(double x, double* s, double* c)
