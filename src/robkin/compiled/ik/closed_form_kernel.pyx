"""The base of the closed-form IK kernels: the batch loop and the single-target entry, written once.

A kernel (``closed_form_6r.SphericalWristKernel`` / ``ThreeParallelKernel``,
``closed_form_scara.ScaraKernel``) is built once per robot from the geometry its Python detector found
and implements one C method, ``solve_one``: every branch (S of them) of one target, wrapped into the
joint limits, each marked valid or not, and an outcome code saying which step failed first (0: a valid
branch exists; the codes' meanings are the subclass's). This base turns it into

- ``solve``: a batch of targets, every branch (what ``kinematics.closed_form.Branches`` holds);
- ``nearest``: one target, the verified branch nearest a preference (and with ``every`` all distinct
  verified branches) in one call that builds no batch arrays and returns the finished result: the
  single ``Robot.ik(T)`` path.

Both choose and verify exactly as ``solutions.nearest_verified`` does (the same ``nearest.pxd`` code).
"""

import numpy as np

cimport numpy as cnp
from libc.math cimport isfinite
from libc.stdlib cimport free, malloc
from robkin.compiled.chain.fk cimport Chain
from robkin.compiled.ik.nearest cimport check_work_size, keep_distinct, nearest_branch, put_row, rows_array
from robkin.compiled.runtime.rigid cimport exact_pose
from robkin.compiled.ik.subproblems cimport c_doubles, new_array, read_pose
from robkin.compiled.runtime.threads cimport batch_threads
from cython.parallel cimport parallel, prange

cnp.import_array()

cdef enum:
    # a target takes 1-10 us (up to ~100 us for the general 6R): threads pay from a few hundred targets
    # per thread; chunks of targets keep the dynamic schedule's bookkeeping small beside them
    MIN_TARGETS_PER_THREAD = 256
    TARGETS_PER_CHUNK = 32

cdef extern from "Python.h":
    int PyObject_GenericSetDict(object obj, object value, void* context) except -1


cdef inline bint _positive(object x):
    """x is a Python float, finite and > 0 (anything else is left to the caller's checks)."""
    return type(x) is float and isfinite(<double>x) and <double>x > 0.0


cdef class ClosedFormKernel:
    """Limits, units, the chain and the default preference of one robot; subclasses add the geometry
    and ``solve_one``."""

    def __init__(self, Chain chain, limits, revolute, double scale, double limit_tol, ref0, Py_ssize_t S,
                 Py_ssize_t work_size):
        """chain: the robot's; limits (n, 2); revolute (n,) bool; scale: its size (length units);
        limit_tol: the limits' slack; ref0 (n,): the default preference
        (``kinematics.limits.default_preference``); S branches per target, work_size doubles of
        scratch for ``solve_one``."""
        lim = np.ascontiguousarray(limits, dtype=np.float64)
        rev = np.ascontiguousarray(revolute, dtype=np.uint8)
        n = len(rev)
        if chain.n != n or lim.shape != (n, 2):
            raise ValueError(f"closed-form kernel: expected limits ({chain.n}, 2) and {chain.n} joint types")
        self.n, self.S, self.work_size = n, S, max(work_size, 1)
        self.chain, self.scale, self.limit_tol = chain, scale, limit_tol
        lo, hi = lim[:, 0].copy(), lim[:, 1].copy()
        unit = np.where(rev, 1.0, scale)
        ref0 = np.array(ref0, dtype=np.float64)
        if ref0.shape != (n,):
            raise ValueError(f"ref0: expected shape ({n},)")
        self._owners = (lim, rev, lo, hi, unit, ref0)
        self.lim = <double*>cnp.PyArray_DATA(lim)
        self.rev = <unsigned char*>cnp.PyArray_DATA(rev)
        self.lo = <double*>cnp.PyArray_DATA(lo)
        self.hi = <double*>cnp.PyArray_DATA(hi)
        self.unit = <double*>cnp.PyArray_DATA(unit)
        self.ref0 = <double*>cnp.PyArray_DATA(ref0)

    cdef signed char solve_one(self, const double* Rd, const double* pd, const double* ref, double* Q,
                               unsigned char* valid, double* detail, unsigned char* uncertain,
                               double* work) noexcept nogil:
        """Every branch Q (S, n) of the target (R_d 3x3 row-major, p_d (3,)), preferring ref (n,) for
        free choices; valid (S,), detail (the number the failure message quotes), uncertain (a
        singular target not proven unreachable); work: work_size doubles of scratch. Returns the code."""
        return 0

    def solve(self, targets, q_ref, int threads=0):
        """Every branch of targets (N, 4, 4), preferring q_ref (N, n) for the free choices.

        The targets are split over ``threads`` (0: automatic, see ``threads.pyx``; one thread runs
        without an OpenMP region); each target's branches are the same bits on any thread.
        Returns Q (N, S, n), valid (N, S) bool, code (N,) int8, detail (N,) float, uncertain (N,) bool
        and the number of targets without a valid branch.
        """
        cdef Py_ssize_t n = self.n, S = self.S, k, failed = 0
        cdef cnp.ndarray T = c_doubles(targets, 3, 4, "targets")
        cdef cnp.ndarray R = c_doubles(q_ref, 2, n, "q_ref")
        cdef Py_ssize_t N = cnp.PyArray_DIM(T, 0)
        if cnp.PyArray_DIM(R, 0) != N:
            raise ValueError(f"q_ref: expected {N} rows, got {cnp.PyArray_DIM(R, 0)}")
        cdef cnp.ndarray Q = new_array(3, N, S, n, cnp.NPY_DOUBLE)
        cdef cnp.ndarray valid = new_array(2, N, S, 0, cnp.NPY_BOOL)
        cdef cnp.ndarray code = new_array(1, N, 0, 0, cnp.NPY_INT8)
        cdef cnp.ndarray detail = new_array(1, N, 0, 0, cnp.NPY_DOUBLE)
        cdef cnp.ndarray unc = new_array(1, N, 0, 0, cnp.NPY_BOOL)
        cdef const double* t = <const double*>cnp.PyArray_DATA(T)
        cdef const double* ref = <const double*>cnp.PyArray_DATA(R)
        cdef double* q = <double*>cnp.PyArray_DATA(Q)
        cdef unsigned char* v = <unsigned char*>cnp.PyArray_DATA(valid)
        cdef signed char* c = <signed char*>cnp.PyArray_DATA(code)
        cdef double* det = <double*>cnp.PyArray_DATA(detail)
        cdef unsigned char* u = <unsigned char*>cnp.PyArray_DATA(unc)
        cdef double* work = NULL      # scratch per call, and per thread (not per kernel: see nearest)
        cdef int nt = batch_threads(threads, N, MIN_TARGETS_PER_THREAD), short = 0
        if nt <= 1:     # no OpenMP region: entering one costs as much as solving a target
            work = <double*>malloc(self.work_size * sizeof(double))
            if work == NULL:
                raise MemoryError()
            with nogil:
                for k in range(N):
                    failed += self.branches(t, ref, q, v, c, det, u, k, work)
            free(work)
            return Q, valid, code, detail, unc, failed
        with nogil, parallel(num_threads=nt):
            work = <double*>malloc(self.work_size * sizeof(double))
            for k in prange(N, schedule="dynamic", chunksize=TARGETS_PER_CHUNK):
                if work == NULL:
                    short += 1    # a reduction: any thread that ran out of memory counts
                    continue
                failed += self.branches(t, ref, q, v, c, det, u, k, work)
            free(work)
        if short:
            raise MemoryError()
        return Q, valid, code, detail, unc, failed

    cdef int branches(self, const double* t, const double* ref, double* q, unsigned char* v,
                             signed char* c, double* det, unsigned char* u, Py_ssize_t k,
                             double* work) noexcept nogil:
        """Target k of ``solve``: its branches into its rows of the outputs; 1 if none is valid."""
        cdef double Rd[9]
        cdef double pd[3]
        cdef Py_ssize_t n = self.n, S = self.S
        read_pose(t + 16 * k, Rd, pd)
        c[k] = self.solve_one(Rd, pd, ref + n * k, q + S * n * k, v + S * k, det + k, u + k, work)
        return c[k] != 0

    def nearest(self, target, q_ref, tol_position, tol_orientation, bint every, double same_tol,
                result_type, str method, embed=None):
        """One target: the verified branch nearest the preference, in one call without batch arrays.

        Parameters
        ----------
        target : (4, 4) float64 C-contiguous array
            The tool pose; taken only if it is an exact pose (``rigid.exact_pose``).
        q_ref : (n,) array or None
            The preference; None: the default one given at construction.
        tol_position, tol_orientation : float
            The forward-kinematics check (length units, radians); taken only if positive finite floats.
        every : bool
            Also every distinct verified branch (two are the same when no |dq / unit| exceeds
            ``same_tol``), nearest first.
        result_type, method : type, str
            The result to build (``kinematics.ik.IKResult``, a frozen dataclass: built without its
            ``__init__``, as its ``_build``) and the name of the method that solved it.
        embed : (template, where), optional
            The robot is a longer arm with joints held (``kinematics.lock``): q and the solutions come
            back as rows of that arm, the template (m,) float64 with this robot's joint j at where[j]
            ((n,) intp, distinct indices in [0, m)).

        Returns
        -------
        A ``result_type`` with q (n,) (or (m,) with ``embed``), success True, iterations 0, attempts 1,
        position_error and orientation_error (floats), method, message '' and solutions ((k, n) or (k, m)
        with ``every``, else None);
        or None when an input is not of the kinds above or no branch counts: the caller then takes the
        general path, for its checks and messages, the failure's reasons and the numeric retry.
        """
        if not (cnp.PyArray_Check(target) and cnp.PyArray_TYPE(<cnp.ndarray>target) == cnp.NPY_DOUBLE
                and cnp.PyArray_NDIM(<cnp.ndarray>target) == 2 and cnp.PyArray_DIM(<cnp.ndarray>target, 0) == 4
                and cnp.PyArray_DIM(<cnp.ndarray>target, 1) == 4
                and cnp.PyArray_IS_C_CONTIGUOUS(<cnp.ndarray>target)
                and _positive(tol_position) and _positive(tol_orientation)):
            return None
        cdef const double* t = <const double*>cnp.PyArray_DATA(<cnp.ndarray>target)
        if not exact_pose(t):
            return None
        cdef const double* ref = self.ref0
        cdef cnp.ndarray R
        if q_ref is not None:
            R = c_doubles(q_ref, 1, self.n, "q_ref")
            ref = <const double*>cnp.PyArray_DATA(R)
        cdef Py_ssize_t n = self.n, S = self.S, best, m, j, full = n
        cdef const double* template = NULL
        cdef const Py_ssize_t* where = NULL
        cdef cnp.ndarray tpl, places
        if embed is not None:
            tpl, places = embed
            if not (cnp.PyArray_TYPE(tpl) == cnp.NPY_DOUBLE and cnp.PyArray_NDIM(tpl) == 1
                    and cnp.PyArray_IS_C_CONTIGUOUS(tpl) and cnp.PyArray_TYPE(places) == cnp.NPY_INTP
                    and cnp.PyArray_NDIM(places) == 1 and cnp.PyArray_IS_C_CONTIGUOUS(places)
                    and cnp.PyArray_DIM(places, 0) == n):
                raise ValueError(f"embed: expected a float64 template (m,) and {n} intp places")
            full = cnp.PyArray_DIM(tpl, 0)
            template = <const double*>cnp.PyArray_DATA(tpl)
            where = <const Py_ssize_t*>cnp.PyArray_DATA(places)
            for j in range(n):
                if where[j] < 0 or where[j] >= full:
                    raise ValueError(f"embed: place {where[j]} is not an index of the {full} joints")
        cdef double Rd[9]
        cdef double pd[3]
        cdef double detail, ep, eo
        cdef unsigned char uncertain
        # scratch per call (not per kernel: another thread may run the same kernel whenever this one
        # runs Python code, e.g. a garbage collection during an allocation): branches (S, n), distances
        # (S), solve_one's work, nearest_branch's work, the order and the kept rows (2 S), valid and
        # reached flags (2 S)
        cdef Py_ssize_t check_size = check_work_size(S, n, every)
        cdef char* buf = <char*>malloc((S * n + S + self.work_size + check_size) * sizeof(double)
                                       + 2 * S * sizeof(Py_ssize_t) + 2 * S)
        if buf == NULL:
            raise MemoryError()
        cdef double* Q = <double*>buf
        cdef double* dist = Q + S * n
        cdef double* work = dist + S
        cdef double* check_work = work + self.work_size
        cdef Py_ssize_t* order = <Py_ssize_t*>(check_work + check_size)
        cdef unsigned char* valid = <unsigned char*>(order + 2 * S)
        cdef unsigned char* reached = valid + S
        cdef cnp.ndarray q
        try:
            read_pose(t, Rd, pd)
            self.solve_one(Rd, pd, ref, Q, valid, &detail, &uncertain, work)
            best = nearest_branch(self.chain.L, self.rev, n, Q, valid, S, t, ref, self.lim, self.scale,
                                  <double>tol_position, <double>tol_orientation, self.limit_tol, every,
                                  reached, dist, order, &m, &ep, &eo, check_work)
            if best < 0:
                return None
            q = new_array(1, full, 0, 0, cnp.NPY_DOUBLE)
            put_row(Q + best * n, n, template, where, full, <double*>cnp.PyArray_DATA(q))
            solutions = None
            if every:
                m = keep_distinct(Q, n, order, m, reached, self.unit, same_tol, order + S)
                solutions = rows_array(Q, n, order + S, m, template, where, full)
        finally:
            free(buf)
        result = result_type.__new__(result_type)
        # the fields as a new instance dictionary, set past the frozen class's __setattr__
        PyObject_GenericSetDict(result, {"q": q, "success": True, "iterations": 0, "attempts": 1,
                                         "position_error": ep, "orientation_error": eo, "method": method,
                                         "message": "", "solutions": solutions}, NULL)
        return result
