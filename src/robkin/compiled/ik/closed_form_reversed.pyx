"""Compiled closed form of a chain read backwards: a robot solved by the kernel of its reversed chain.

The reversed chain of a robot (``kinematics.pieper.reversed_robot``: base and tool swapped, joints in
reverse order) has FK(q[::-1]) = FK_robot(q)^-1. A robot whose *first* three axes meet is then solved by
the Pieper kernel of its reversed chain, whose *last* three do: the target T becomes T^-1 = (R^T,
-R^T p), the preference is read backwards, and each branch found comes back in reverse order.

``ReversedKernel`` does exactly that inside ``solve_one``, so the base class (``closed_form_kernel``)
gives it the batch loop (threads included) and the single-target ``nearest`` entry with the check of
every branch on the robot's own chain and limits, as for any other kernel: no Python between the
target and the finished result.
"""

cimport numpy as cnp
from robkin.compiled.ik.closed_form_kernel cimport ClosedFormKernel
from robkin.compiled.chain.fk cimport Chain

cnp.import_array()


cdef class ReversedKernel(ClosedFormKernel):
    """The robot's kernel made of ``inner``, the kernel of its reversed chain (same joints, reversed)."""

    cdef ClosedFormKernel inner

    def __init__(self, Chain chain, limits, revolute, double scale, double limit_tol, ref0,
                 ClosedFormKernel inner):
        """chain, limits (n, 2), revolute (n,), scale, limit_tol, ref0 (n,): the robot's (see
        ``ClosedFormKernel``); inner: the kernel built for the reversed chain, with as many joints."""
        if inner.n != chain.n:
            raise ValueError(f"reversed kernel: the inner kernel has {inner.n} joints, the chain {chain.n}")
        # the inner kernel's scratch, then the preference read backwards
        ClosedFormKernel.__init__(self, chain, limits, revolute, scale, limit_tol, ref0, inner.S,
                                  inner.work_size + inner.n)
        self.inner = inner

    cdef signed char solve_one(self, const double* Rd, const double* pd, const double* ref, double* Q,
                               unsigned char* valid, double* detail, unsigned char* uncertain,
                               double* work) noexcept nogil:
        """The inner kernel on the inverse target with the preference reversed, each branch reversed."""
        cdef double Ri[9]
        cdef double pi[3]
        cdef Py_ssize_t n = self.n, i, j, s
        cdef double* rref = work
        cdef double tmp
        cdef signed char code
        for i in range(3):
            for j in range(3):
                Ri[3 * i + j] = Rd[3 * j + i]
            # -(R^T p), the sum in the order of se3.inv's einsum
            pi[i] = -((Rd[i] * pd[0] + Rd[3 + i] * pd[1]) + Rd[6 + i] * pd[2])
        for j in range(n):
            rref[j] = ref[n - 1 - j]
        code = self.inner.solve_one(Ri, pi, rref, Q, valid, detail, uncertain, work + n)
        for s in range(self.S):
            for j in range(n // 2):
                tmp = Q[s * n + j]
                Q[s * n + j] = Q[s * n + n - 1 - j]
                Q[s * n + n - 1 - j] = tmp
        return code
