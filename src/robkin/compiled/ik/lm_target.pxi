# One target of the Levenberg-Marquardt solver (included by lm.pyx; see its docstring for the method):
# the parameters, the restart stream, the damped step, the residual and the attempts of one target.


cdef struct Params:
    int n
    int max_iter
    int restarts
    int stall_window
    int check_iteration
    int limit_check_iteration
    double tol_p
    double tol_o
    double tau
    double mu_stuck
    double stall_ratio
    double check_E
    double limit_check_E
    double scale
    bint limited
    const double* alpha     # (n,) the R_d sequence's step per joint (restart starts)


cdef inline uint64_t splitmix64(uint64_t* state) noexcept nogil:
    """Next value of the splitmix64 stream (Steele, Lea & Flood 2014): 64 well-mixed bits."""
    cdef uint64_t z
    state[0] += <uint64_t>0x9E3779B97F4A7C15
    z = state[0]
    z = (z ^ (z >> 30)) * <uint64_t>0xBF58476D1CE4E5B9
    z = (z ^ (z >> 27)) * <uint64_t>0x94D049BB133111EB
    return z ^ (z >> 31)


cdef inline double uniform01(uint64_t* state) noexcept nogil:
    """Uniform double in [0, 1) from the top 53 bits."""
    return <double>(splitmix64(state) >> 11) * (1.0 / 9007199254740992.0)


cdef inline void damped_step(const double* J, const double* e, double mu, int n, double* h) noexcept nogil:
    """h (n) = (J^T J + mu I)^-1 J^T e for J (6 x n): through the 6 x 6 system J J^T + mu I when
    n >= 6 (push-through identity), else through the n x n one. mu > 0 keeps both definite."""
    cdef double A[36]
    cdef double y[6]
    cdef int i, j, k
    cdef double s
    if n >= 6:
        for i in range(6):
            for j in range(i + 1):
                s = 0.0
                for k in range(n):
                    s += J[i * n + k] * J[j * n + k]
                A[i * 6 + j] = s
            A[i * 6 + i] += mu
            y[i] = e[i]
        if not cholesky_solve(A, y, 6):
            for k in range(n):
                h[k] = 0.0
            return
        for k in range(n):
            s = 0.0
            for i in range(6):
                s += J[i * n + k] * y[i]
            h[k] = s
        return
    for i in range(n):
        for j in range(i + 1):
            s = 0.0
            for k in range(6):
                s += J[k * n + i] * J[k * n + j]
            A[i * n + j] = s
        A[i * n + i] += mu
        s = 0.0
        for k in range(6):
            s += J[k * n + i] * e[k]
        h[i] = s
    if not cholesky_solve(A, h, n):
        for k in range(n):
            h[k] = 0.0


cdef inline double joint_unit(Chain chain, const Params* P, int j) noexcept nogil:
    """The unit of joint j's step (module doc): 1 rad for a revolute joint, the robot's size for a
    prismatic one."""
    return 1.0 if chain.rev[j] else P.scale


cdef inline double evaluate(Chain chain, const Params* P, const double* w, const double* Td,
                            const double* q, double* e, double* J) noexcept nogil:
    """Weighted residual e (6) and Jacobian J (6 x n, per unit-free joint step) at q; returns
    E = |e|^2 / 2."""
    cdef double T[16]
    cdef double M[9]
    cdef int i, j, n = P.n
    jacobian_one(chain.L, chain.rev, n, q, 0, J, T)
    e[0] = Td[3] - T[3]
    e[1] = Td[7] - T[7]
    e[2] = Td[11] - T[11]
    # M = R_d R^T
    for i in range(3):
        for j in range(3):
            M[3 * i + j] = Td[4 * i] * T[4 * j] + Td[4 * i + 1] * T[4 * j + 1] + Td[4 * i + 2] * T[4 * j + 2]
    rot_log(M, e + 3)
    for i in range(6):
        e[i] *= w[i]
        for j in range(n):
            J[i * n + j] *= w[i] * joint_unit(chain, P, j)
    return 0.5 * (e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3] + e[4] * e[4] + e[5] * e[5])


cdef inline bint converged(const Params* P, const double* e) noexcept nogil:
    # e is weighted: position rows are in units of the robot's size. Half the tolerance: the caller
    # re-checks with Robot.fk, whose rounding (~1e-15 relative) must not flip a verdict.
    cdef double ep = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) * P.scale
    cdef double eo = sqrt(e[3] * e[3] + e[4] * e[4] + e[5] * e[5])
    return ep <= 0.5 * P.tol_p and eo <= 0.5 * P.tol_o


cdef bint solve_one(Chain chain, const Params* P, const double* w, const double* lo, const double* hi,
                    const unsigned char* wrap, const double* rlo, const double* rhi, const double* Td,
                    const double* q0, uint64_t seed, double* work, double* q_out, long* iterations,
                    long* attempts) noexcept nogil:
    """One target: attempts from q0 (clipped into the limits), then random restarts, until converged.

    q_out receives the converged configuration, or the best one found (smallest E). ``work`` holds
    24 n + 6 + stall_window doubles.
    """
    cdef int n = P.n, i, j, it, attempt, slot
    cdef double* q = work
    cdef double* qt = q + n
    cdef double* h = qt + n
    cdef double* hb = h + n
    cdef double* best_q = hb + n
    cdef double* Jh = best_q + n          # 6 used
    cdef double* blocked = Jh + 6         # n used, 0/1
    cdef double* J = blocked + n
    cdef double* Jt = J + 6 * n
    cdef double* Jb = Jt + 6 * n
    cdef double* Ewin = Jb + 6 * n
    cdef double* shift = Ewin + P.stall_window   # n used: this target's random shift of the R_d sequence
    cdef double e[6]
    cdef double et[6]
    cdef double E, Et, mu, nu, diag, diag_max, predicted, actual, rho, x, before, two_pi = 2.0 * M_PI
    cdef double best_E = INFINITY
    cdef bint stalled, stuck, hasty, any_blocked, at_limit, accept
    cdef uint64_t state = seed
    cdef long total_it = 0
    cdef double* swap
    for attempt in range(P.restarts + 1):
        attempts[0] = attempt + 1
        for j in range(n):
            if attempt == 0:
                x = q0[j]
                q[j] = lo[j] if x < lo[j] else (hi[j] if x > hi[j] else x)
                best_q[j] = q[j]      # defined even if no attempt ever has a finite E
            else:
                # restarts walk the R_d sequence (Roberts' additive recurrence, see robkin.samples), shifted
                # by a random offset per target: successive starts spread evenly over the whole box of
                # the limits, its corners and edges included, where uniform draws leave gaps and clumps
                if attempt == 1:
                    shift[j] = uniform01(&state)
                x = shift[j] + attempt * P.alpha[j]
                x -= <double>(<long>x)
                q[j] = rlo[j] + (rhi[j] - rlo[j]) * x
        E = evaluate(chain, P, w, Td, q, e, J)
        # largest diagonal entry of J^T J; the floor keeps the damping positive for a zero Jacobian
        diag_max = 1e-12
        for j in range(n):
            diag = 0.0
            for i in range(6):
                diag += J[i * n + j] * J[i * n + j]
            if diag > diag_max:
                diag_max = diag
        mu = P.tau * diag_max
        nu = 2.0
        for i in range(P.stall_window):
            Ewin[i] = INFINITY
        Ewin[0] = E
        stalled = False
        # the early give-up rules apply while a target has used at most half its attempts: after that
        # every attempt runs its full course (geometries where convergence is slower than on the arms
        # the rules were tuned on, e.g. long prismatic travel)
        hasty = attempt + 1 <= (P.restarts + 1) // 2
        it = 0
        while True:
            if converged(P, e):
                for j in range(n):
                    q_out[j] = q[j]
                iterations[0] = total_it + it
                return True
            stuck = it >= P.max_iter or stalled or mu > P.mu_stuck * diag_max \
                or (hasty and it >= P.check_iteration and E > P.check_E)
            if not stuck and P.limited and hasty and it == P.limit_check_iteration and E > P.limit_check_E:
                for j in range(n):
                    if q[j] <= lo[j] + LIMIT_TOL or q[j] >= hi[j] - LIMIT_TOL:
                        stuck = True
                        break
            if stuck:
                total_it += it
                if E < best_E:
                    best_E = E
                    for j in range(n):
                        best_q[j] = q[j]
                break
            # --- one damped Gauss-Newton step
            damped_step(J, e, mu, n, h)
            if P.limited:
                # joints already on a limit and pushed past it are frozen for this step and the step
                # is solved again without them, so the others keep making progress along the limit
                any_blocked = False
                for j in range(n):
                    x = q[j] + h[j] * joint_unit(chain, P, j)
                    at_limit = (x < lo[j] and q[j] <= lo[j] + LIMIT_TOL) or (x > hi[j] and q[j] >= hi[j] - LIMIT_TOL)
                    blocked[j] = 1.0 if at_limit else 0.0
                    any_blocked = any_blocked or at_limit
                if any_blocked:
                    for i in range(6):
                        for j in range(n):
                            Jb[i * n + j] = 0.0 if blocked[j] != 0.0 else J[i * n + j]
                    damped_step(Jb, e, mu, n, hb)
                    for j in range(n):
                        h[j] = 0.0 if blocked[j] != 0.0 else hb[j]
                for j in range(n):
                    x = q[j] + h[j] * joint_unit(chain, P, j)
                    if wrap[j]:
                        if x > hi[j]:
                            x -= two_pi * ceil((x - hi[j]) / two_pi)
                        elif x < lo[j]:
                            x += two_pi * ceil((lo[j] - x) / two_pi)
                    x = lo[j] if x < lo[j] else (hi[j] if x > hi[j] else x)
                    qt[j] = x
                    # the step actually taken, before whole turns (which change no pose) are taken off
                    if not wrap[j]:
                        h[j] = (x - q[j]) / joint_unit(chain, P, j)
            else:
                for j in range(n):
                    qt[j] = q[j] + h[j] * joint_unit(chain, P, j)
            predicted = 0.0
            x = 0.0
            for i in range(6):
                Jh[i] = 0.0
                for j in range(n):
                    Jh[i] += J[i * n + j] * h[j]
                predicted += e[i] * Jh[i]
                x += Jh[i] * Jh[i]
            predicted -= 0.5 * x
            Et = evaluate(chain, P, w, Td, qt, et, Jt)
            actual = E - Et
            accept = actual > 0.0 and predicted > 0.0
            # Nielsen's damping update: shrink by up to 3 on a good step, grow geometrically on a bad
            # one; floor: relative damping below 1e-12 changes no step measurably, and keeps J^T J + mu I
            # (singular for a redundant arm) safely invertible (condition number <= 1e12)
            if accept:
                rho = actual / predicted
                x = 1.0 - (2.0 * rho - 1.0) ** 3
                mu *= x if x > 1.0 / 3.0 else 1.0 / 3.0
                nu = 2.0
                swap = q
                q = qt
                qt = swap
                swap = J
                J = Jt
                Jt = swap
                for i in range(6):
                    e[i] = et[i]
                E = Et
            else:
                mu *= nu
                nu *= 2.0
            if mu < 1e-12 * diag_max:
                mu = 1e-12 * diag_max
            # stall test: E now against E stall_window iterations ago (a ring buffer, inf-filled)
            it += 1
            slot = it % P.stall_window
            before = Ewin[slot]
            Ewin[slot] = E
            stalled = E > (1.0 - P.stall_ratio) * before
    for j in range(n):
        q_out[j] = best_q[j]
    iterations[0] = total_it
    return False
