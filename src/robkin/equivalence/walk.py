"""The joint-by-joint search behind ``equivalence.compare``: a joint mapping q_A = s q_B + delta under
which every axis of B is the matching axis of A moved by the offsets before it (the method is in
``equivalence``'s docstring), and, where none exists, the deepest joint that cannot be matched and how
it differs.

Screws are (w, v) in the base frame; lengths are compared relative to the robot size ``scale``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable, Sequence

import numpy as np

from .. import se3
from ..robot import Robot

#: a residual of joint offsets x (k,) -> (m,), driven to zero by the solvers below
Residual = Callable[[np.ndarray], np.ndarray]

__all__ = ["Walk", "pose_difference"]


def _scaled(S: np.ndarray, scale: float, slide: bool) -> np.ndarray:
    """A screw (or a change of one) in dimensionless units: a revolute screw (w, v) has v = -w x p,
    a length, divided by the robot size; a prismatic screw (0, v) is a direction, kept as it is."""
    return S.copy() if slide else np.concatenate([S[:3], S[3:] / scale])


def _is_slide(S: np.ndarray) -> bool:
    """A unit screw with w = 0 (|w| is 0 or 1 for the screws compared here)."""
    return bool(np.linalg.norm(S[:3]) < 0.5)


def _screw_error(Sa: np.ndarray, Sb: np.ndarray, scale: float) -> float:
    slide = _is_slide(Sa)
    return float(np.abs(_scaled(Sa, scale, slide) - _scaled(Sb, scale, slide)).max())


def _effect(S_open: np.ndarray, open_slide: bool, Si: np.ndarray, scale: float) -> np.ndarray:
    """How axis Si changes per natural step of an open joint (1 rad, or one robot size of slide),
    in Si's dimensionless units: the Lie bracket [S_open, Si], scaled."""
    return _scaled(_bracket(S_open, Si), scale, _is_slide(Si)) * (scale if open_slide else 1.0)


def pose_difference(Ta: np.ndarray, Tb: np.ndarray) -> tuple[float, float]:
    """(translation distance, rotation angle in rad) between two poses."""
    dR = Ta[:3, :3].T @ Tb[:3, :3]
    angle = math.acos(max(-1.0, min(1.0, (float(np.trace(dR)) - 1.0) / 2.0)))
    return float(np.linalg.norm(Ta[:3, 3] - Tb[:3, 3])), angle


def _line(S: np.ndarray, revolute: bool) -> tuple[np.ndarray, np.ndarray]:
    """(direction, point closest to the origin) of a screw's axis (prismatic: through the origin)."""
    if revolute:
        return S[:3], np.cross(S[:3], S[3:])
    return S[3:], np.zeros(3)


def _describe(Sa: np.ndarray, Sb: np.ndarray, revolute: bool) -> str:
    """How two unit screws of the same joint type differ: direction angle, or line distance."""
    ua, pa = _line(Sa, revolute)
    ub, pb = _line(Sb, revolute)
    cosang = float(np.clip(np.dot(ua, ub), -1.0, 1.0))
    angle = math.degrees(math.acos(cosang))
    if revolute:
        from ..lines import common_normal

        dist = common_normal(pa, ua, pb, ub).distance
    else:
        dist = 0.0
    if min(angle, 180.0 - angle) > 1e-6:
        text = f"axis direction differs by {angle:.4g} deg"
        if revolute:
            text += f" (axes {dist:.4g} m apart at their closest)"
        return text
    way = "the same way" if angle < 90 else "opposite ways"
    return f"axis position differs: parallel axes pointing {way}, {dist:.4g} m apart"


@dataclass
class _State:
    """A partial joint mapping: G (offsets applied so far) and the joints whose offsets are still open.

    Open ("pending") joints commute with every joint matched after them (that is why they are still
    open), so their offsets can be applied later by left-multiplying G. Slides whose offsets were
    only partly fixed stay open with linear ``constraints`` (joint indices, matrix C): any further
    change x of their offsets must keep C x = 0, so the axes they already placed stay put.
    """

    G: np.ndarray
    pending: tuple[int, ...]
    signs: np.ndarray
    offsets: np.ndarray
    constraints: tuple[tuple[tuple[int, ...], np.ndarray], ...] = ()


@dataclass
class _Result:
    matched: int
    signs: np.ndarray
    offsets: np.ndarray
    failure: str | None = None
    tool: str = "not compared"


def _bracket(S1: np.ndarray, S2: np.ndarray) -> np.ndarray:
    """Lie bracket [S1, S2] of screws (w, v): how S2 changes under an infinitesimal motion along S1."""
    w1, v1, w2, v2 = S1[:3], S1[3:], S2[:3], S2[3:]
    return np.concatenate([np.cross(w1, w2), np.cross(w1, v2) + np.cross(v1, w2)])


def _motion(screws: list[np.ndarray], d: np.ndarray) -> np.ndarray:
    """Product of exp([S_k] d_k) (the screws commute, so the order does not matter)."""
    E = np.eye(4)
    for S, x in zip(screws, d):
        E = E @ se3.exp_twist(S, x)
    return E


def _offset_candidates(pending: np.ndarray, Sa: np.ndarray, Sb: np.ndarray, scale: float
                       ) -> list[tuple[float, int, float]]:
    """Rotations d about one open revolute joint (screw ``pending``) with Ad(exp([pending] d)) Sa = sign * Sb.

    The moved screw is c0 + c1 cos d + c2 sin d (sampled at d = 0, pi/2, pi), so each sign's best d
    is a 2x2 least-squares solve in scaled coordinates. Both signs can fit (a rotation by pi about
    a perpendicular axis reverses a line), which is why the caller searches over the candidates.
    Returns (d, sign, residual), best first.
    """
    slide = _is_slide(Sa)

    def moved(d: float) -> np.ndarray:
        return _scaled(se3.adjoint(se3.exp_twist(pending, d)) @ Sa, scale, slide)

    s0, s_half, s_pi = moved(0.0), moved(math.pi / 2), moved(math.pi)
    c0, c1 = (s0 + s_pi) / 2, (s0 - s_pi) / 2
    C = np.column_stack([c1, s_half - c0])
    out = []
    for sign in (1, -1):
        x = np.linalg.lstsq(C, sign * _scaled(Sb, scale, slide) - c0, rcond=None)[0]
        d = math.atan2(x[1], x[0])
        out.append((d, sign, float(np.abs(moved(d) - sign * _scaled(Sb, scale, slide)).max())))
    return sorted(out, key=lambda c: c[2])


def _linear_solve(residual: Residual, k: int, extra: np.ndarray) -> tuple[np.ndarray, float, int]:
    """Least-norm x for an affine residual(x) = r0 + J x (slides only), with extra rows extra @ x = 0.

    Returns (x, largest residual, rank of the stacked system).
    """
    r0 = residual(np.zeros(k))
    J = np.column_stack([residual(e) - r0 for e in np.eye(k)])
    A = np.vstack([J, extra]) if extra.size else J
    rhs = np.concatenate([-r0, np.zeros(A.shape[0] - J.shape[0])])
    x = np.linalg.lstsq(A, rhs, rcond=None)[0]
    # rank with a relative threshold: columns are O(1) (unit slides, scaled), rounding is ~1e-15
    rank = int(np.linalg.matrix_rank(A, tol=1e-9 * max(1.0, float(np.abs(A).max()))))
    return x, float(np.abs(residual(x)).max()), rank


#: Forward-difference step of ``_nonlinear_solve``'s Jacobian, relative to max(1, |x|): sqrt(machine
#: epsilon) balances truncation (~h) against rounding (~eps / h) for residuals of size ~1 (they are
#: scaled screws), the usual choice (scipy's '2-point' default too).
_FD_STEP = 2.0 ** -26


def _nonlinear_solve(screws: list[np.ndarray], revolute: list[bool], residual: Residual,
                     tol: float) -> list[np.ndarray]:
    """Offsets of two or more open joints including a rotation (rare: a rotation and a slide along
    the same line), from a few starts, by robkin's compiled Levenberg-Marquardt (``box_lsq``, the
    synthesis optimiser's solver; unbounded here) on a forward-difference Jacobian."""
    import itertools

    from ..compiled.runtime.box_lsq import solve

    k = len(revolute)
    free = np.full(k, np.inf)

    def jacobian(x: np.ndarray) -> np.ndarray:
        r0 = residual(x)
        h = _FD_STEP * np.maximum(1.0, np.abs(x))
        return np.column_stack([(residual(x + h[i] * e) - r0) / h[i] for i, e in enumerate(np.eye(k))])

    found: list[np.ndarray] = []
    choices = [(0.0, math.pi / 2, math.pi, -math.pi / 2) if r else (0.0,) for r in revolute]
    for x0 in itertools.islice(itertools.product(*choices), 16):
        # tolerances at rounding: the solution must meet ``tol`` (~1e-9 relative), far below any stop
        x = solve(residual, jacobian, np.array(x0), -free, free, ftol=1e-15, xtol=1e-15, gtol=1e-15,
                  max_nfev=200)[0]
        d = np.where(revolute, (x + math.pi) % (2 * math.pi) - math.pi, x)
        if np.abs(residual(d)).max() <= tol and not any(np.allclose(d, f, atol=1e-9) for f in found):
            found.append(d)
    return found


class Walk:
    """Depth-first search for a joint mapping, preferring sign +1 and offset 0 at every joint.

    At joint i the open joints that move axis i (non-zero Lie bracket with it) get their offsets:
    one revolute in closed form (``_offset_candidates``), slides by a linear least-squares solve
    (which may leave some of them open, see ``_State``), a rotation with slides by a small nonlinear
    solve. Usually at most two candidates (the two signs) exist, so the search is cheap. Without a
    full mapping, the deepest failure is the diagnosis.
    """

    def __init__(self, a: Robot, b: Robot, SA: np.ndarray, SB: np.ndarray, scale: float, tol: float) -> None:
        self.a, self.b, self.SA, self.SB, self.scale, self.tol = a, b, SA, SB, scale, tol
        self.deepest: _Result | None = None

    def run(self, n: int) -> _Result:
        start = _State(np.eye(4), (), np.ones(n, dtype=int), np.zeros(n))
        found = self._step(0, n, start)
        if found is not None:
            return found
        # a failed search has always recorded where it failed
        return self.deepest or _Result(0, start.signs, start.offsets, "no joint could be matched")

    def _fail(self, i: int, state: _State, why: str, tool: str = "not compared") -> None:
        # keep the first failure at the deepest joint: the search tries the preferred mapping first
        d = self.deepest
        if d is None or i > d.matched or (i == d.matched and d.tool == "not compared" and tool != "not compared"):
            self.deepest = _Result(i, state.signs.copy(), state.offsets.copy(), why, tool)

    def _open_screws(self, st: _State, which: Sequence[int]) -> list[np.ndarray]:
        return [se3.adjoint(st.G) @ self.SA[p] for p in which]

    def _extra_rows(self, st: _State, idx: list[int]) -> np.ndarray:
        """Constraint rows of ``st`` restricted to the joints ``idx`` (others do not move now)."""
        rows = []
        for joints, C in st.constraints:
            if any(p in idx for p in joints):
                block = np.zeros((C.shape[0], len(idx)))
                for c, p in enumerate(joints):
                    if p in idx:
                        block[:, idx.index(p)] = C[:, c]
                rows.append(block)
        return np.vstack(rows) if rows else np.zeros((0, len(idx)))

    def _solutions(self, st: _State, idx: list[int], residual: Residual) -> list[tuple[np.ndarray, bool]]:
        """Offsets for the open joints ``idx`` making ``residual`` vanish: (x, all determined)."""
        screws = self._open_screws(st, idx)
        rev = [self.a.joints[p].revolute for p in idx]
        if not any(rev):
            x, res, rank = _linear_solve(residual, len(idx), self._extra_rows(st, idx))
            return [(x, rank == len(idx))] if res <= self.tol else []
        extra = self._extra_rows(st, idx)
        if extra.size:  # keep the axes the open slides already placed (their constraint rows)
            plain = residual

            def residual(x: np.ndarray) -> np.ndarray:
                return np.concatenate([plain(x), extra @ x])
        return [(x, True) for x in _nonlinear_solve(screws, rev, residual, self.tol)]

    def _step(self, i: int, n: int, st: _State) -> _Result | None:
        a, b, tol, scale = self.a, self.b, self.tol, self.scale
        if i == n:
            return self._tool(n, st)
        ja, jb = a.joints[i], b.joints[i]
        if ja.type != jb.type:
            self._fail(i, st, f"type {ja.type} in A, {jb.type} in B")
            return None
        Sa = se3.adjoint(st.G) @ self.SA[i]
        Sb = self.SB[i]
        open_screws = self._open_screws(st, st.pending)
        movers = [p for p, S in zip(st.pending, open_screws)
                  if np.abs(_effect(S, not a.joints[p].revolute, Sa, scale)).max() > tol]
        # options: (offset changes of open joints, sign, the open joints now determined)
        options: list[tuple[dict[int, float], int, set[int]]] = []
        explained = ""
        # the offsets so far may already place axis i: no change (revolute movers are then fixed at
        # their current offset, slides stay open under the constraint of keeping axis i in place)
        fixed_now = {p for p in movers if a.joints[p].revolute}
        for sign in (1, -1):
            if _screw_error(Sa, sign * Sb, scale) <= tol:
                options.append(({}, sign, fixed_now))
        if movers:
            screws = self._open_screws(st, movers)
            if len(movers) == 1 and a.joints[movers[0]].revolute:
                sols = [(np.array([d]), sign, set(movers))
                        for d, sign, res in _offset_candidates(screws[0], Sa, Sb, scale) if res <= tol]
            else:
                sols = []
                for sign in (1, -1):
                    def residual(x: np.ndarray, sign: int = sign) -> np.ndarray:
                        return _scaled(se3.adjoint(_motion(screws, x)) @ Sa - sign * Sb, scale, not ja.revolute)
                    # rotations are fixed by the solve; slides stay open unless the axes placed so
                    # far pin them down (``_advance`` checks the rank)
                    sols += [(x, sign, fixed_now) for x, _ in self._solutions(st, movers, residual)]
            # prefer sign +1, then the smaller offsets (slides relative to the robot size)
            unit = np.array([1.0 if a.joints[p].revolute else scale for p in movers])
            sols.sort(key=lambda c: (c[1] != 1, float(np.abs(c[0] / unit).sum())))
            options += [(dict(zip(movers, x)), sign, det) for x, sign, det in sols
                        if np.abs(x / unit).max() > tol or not any(o[1] == sign for o in options)]
            if not options:
                explained = f"; no zero offset of joint {', '.join(str(p + 1) for p in movers)} explains it"
        if not options:
            self._fail(i, st, _describe(Sa, Sb, ja.revolute) + explained)
            return None
        for solved, sign, determined in options:
            nxt = self._advance(st, i, movers, solved, sign, determined)
            found = self._step(i + 1, n, nxt)
            if found is not None:
                return found
        return None

    def _advance(self, st: _State, i: int, movers: list[int], solved: dict[int, float], sign: int,
                 determined: set[int]) -> _State:
        """The state after matching joint i: offset changes ``solved``, ``determined`` joints closed."""
        a, scale, tol = self.a, self.scale, self.tol
        idx = list(solved)
        G = _motion(self._open_screws(st, idx), np.array([solved[p] for p in idx])) @ st.G if idx else st.G
        offsets = st.offsets.copy()
        for p, x in solved.items():
            offsets[p] += x
        still = [p for p in st.pending if p not in determined]
        constraints = tuple(c for c in st.constraints if not any(p in determined for p in c[0]))
        Si = se3.adjoint(G) @ self.SA[i]
        kept = [p for p in movers if p not in determined]
        if kept:
            # movers left open (slides only partly fixed by axis i): later changes of their offsets
            # must not move axis i; the rows are the derivatives of axis i along each of them
            moved = replace(st, G=G)
            rows = np.array([_effect(S, True, Si, scale) for S in self._open_screws(moved, kept)]).T
            constraints = constraints + ((tuple(kept), rows),)
            stacked = self._extra_rows(replace(st, constraints=constraints), kept)
            if np.linalg.matrix_rank(stacked, tol=1e-9 * max(1.0, float(np.abs(stacked).max()))) == len(kept):
                # no change of their offsets keeps every placed axis: they are determined after all
                still = [p for p in still if p not in kept]
                constraints = tuple(c for c in constraints if not any(p in kept for p in c[0]))
        # an open joint on the same line as joint i (same type) merges its offset into joint i's
        merged = [p for p in still if a.joints[p].type == a.joints[i].type and min(
            _screw_error(se3.adjoint(G) @ self.SA[p], Si, scale),
            _screw_error(se3.adjoint(G) @ self.SA[p], -Si, scale)) <= tol]
        still = [p for p in still if p not in merged]
        constraints = tuple(c for c in constraints if not any(p in merged for p in c[0]))
        signs = st.signs.copy()
        signs[i] = sign
        return _State(G, tuple(still) + (i,), signs, offsets, constraints)

    def _tool(self, n: int, st: _State) -> _Result | None:
        tol, scale = self.tol, self.scale
        Ma, Mb = st.G @ self.a.tool, self.b.tool
        offsets = st.offsets.copy()
        dist, ang = pose_difference(Ma, Mb)
        if st.pending and not (dist <= tol * scale and ang <= tol):
            idx = list(st.pending)
            screws = self._open_screws(st, idx)

            def residual(x: np.ndarray) -> np.ndarray:
                T = _motion(screws, x) @ Ma
                return np.concatenate([(T[:3, :3] - Mb[:3, :3]).ravel(), (T[:3, 3] - Mb[:3, 3]) / scale])

            if len(idx) == 1 and self.a.joints[idx[0]].revolute:
                R = (Mb @ se3.inv(Ma))[:3, :3]
                w = screws[0][:3]
                sols = [np.array([math.atan2(0.5 * float(np.dot(w, [R[2, 1] - R[1, 2], R[0, 2] - R[2, 0],
                                                                     R[1, 0] - R[0, 1]])),
                                             0.5 * (float(np.trace(R)) - 1.0))])]
            else:
                sols = [x for x, _ in self._solutions(st, idx, residual)]
            for x in sols:
                T = _motion(screws, x) @ Ma
                d2, a2 = pose_difference(T, Mb)
                if d2 <= tol * scale and a2 <= tol:
                    for p, v in zip(idx, x):
                        offsets[p] += v
                    Ma, dist, ang = T, d2, a2
                    break
        if dist <= tol * scale and ang <= tol:
            return _Result(n, st.signs.copy(), offsets, None, "same")
        self._fail(n, replace(st, offsets=offsets), "",
                   f"differs: position by {dist:.4g} m, rotation by {math.degrees(ang):.4g} deg")
        return None
