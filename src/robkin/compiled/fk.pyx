# cython: language_level=3
"""Forward kinematics and the frames along the chain, single configuration and batch.

``Chain`` holds a robot's fixed transforms once (built by ``Robot``, cached on it); its methods take
joint values and return new numpy arrays. They validate nothing beyond what they need to stay memory
safe: they return ``None`` unless q is a C-contiguous float64 array of shape (n,) or (N, n) with only
finite values, and the Python wrapper (``Robot.fk``) then validates and explains.
"""

cimport numpy as cnp
from robkin.compiled.fk cimport walk_tool, walk_frames, usable_q, empty_result

import numpy as np

cnp.import_array()


cdef class Chain:
    """The fixed transforms L (n+1, 4, 4) and joint types of a robot, for the compiled kernels.

    Parameters
    ----------
    L : (n+1, 4, 4) float array
        T(q) = L_1 Z_1(q_1) ... L_n Z_n(q_n) L_{n+1} (see ``fk.pxd``).
    revolute : (n,) bool array
    """

    def __cinit__(self, L, revolute):
        cdef cnp.ndarray La = np.ascontiguousarray(L, dtype=np.float64)
        cdef cnp.ndarray ra = np.ascontiguousarray(revolute, dtype=np.uint8)
        if La.ndim != 3 or La.shape[1] != 4 or La.shape[2] != 4 or La.shape[0] != ra.shape[0] + 1 \
                or ra.shape[0] < 1:
            raise ValueError("Chain: expected L (n+1, 4, 4) and revolute (n,)")
        self.n = ra.shape[0]
        self._L_owner = La
        self._rev_owner = ra
        self.L = <double*>cnp.PyArray_DATA(La)
        self.rev = <unsigned char*>cnp.PyArray_DATA(ra)

    def fk(self, q):
        """Tool pose (4, 4) for q (n,), or (N, 4, 4) for q (N, n); None if q is not usable as is."""
        cdef Py_ssize_t k, N
        cdef const double* Q
        cdef double* O
        if not usable_q(q, self.n):
            return None
        out = empty_result(q, 4, 4, 0)
        Q = <const double*>cnp.PyArray_DATA(q)
        O = <double*>cnp.PyArray_DATA(out)
        N = cnp.PyArray_SIZE(q) // self.n
        with nogil:
            for k in range(N):
                walk_tool(self.L, self.rev, self.n, Q + k * self.n, O + 16 * k)
        return out

    def frames(self, q):
        """Frames after each joint's motion and the tool: (n+1, 4, 4) for q (n,), (N, n+1, 4, 4) for
        q (N, n); None if q is not usable as is."""
        cdef Py_ssize_t k, N, m = 16 * (self.n + 1)
        cdef const double* Q
        cdef double* O
        if not usable_q(q, self.n):
            return None
        out = empty_result(q, self.n + 1, 4, 4)
        Q = <const double*>cnp.PyArray_DATA(q)
        O = <double*>cnp.PyArray_DATA(out)
        N = cnp.PyArray_SIZE(q) // self.n
        with nogil:
            for k in range(N):
                walk_frames(self.L, self.rev, self.n, Q + k * self.n, O + k * m)
        return out
