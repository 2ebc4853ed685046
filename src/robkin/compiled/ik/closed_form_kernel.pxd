# cython: language_level=3
"""The base of the closed-form IK kernels (``closed_form_6r``, ``closed_form_scara``): see its .pyx."""

from robkin.compiled.chain.fk cimport Chain


cdef class ClosedFormKernel:
    cdef readonly Py_ssize_t n          # joints
    cdef readonly Py_ssize_t S          # branches per target
    cdef Py_ssize_t work_size           # doubles of scratch that solve_one needs
    cdef double scale, limit_tol        # the robot's size (length units); the limits' slack
    cdef Chain chain                    # the robot's compiled chain: the forward-kinematics check
    cdef double* lo                     # (n,) lower limits
    cdef double* hi                     # (n,) upper limits
    cdef double* lim                    # (n, 2) limits, row-major
    cdef unsigned char* rev             # (n,) 1 = revolute
    cdef double* unit                   # (n,) 1 rad for revolute joints, scale for prismatic ones
    cdef double* ref0                   # (n,) the default preference: zero clipped into the limits
    cdef object _owners                 # the numpy arrays owning the memory above

    cdef signed char solve_one(self, const double* Rd, const double* pd, const double* ref, double* Q,
                               unsigned char* valid, double* detail, unsigned char* uncertain,
                               double* work) noexcept nogil
    cdef int branches(self, const double* t, const double* ref, double* q, unsigned char* v, signed char* c,
                      double* det, unsigned char* u, Py_ssize_t k, double* work) noexcept nogil
