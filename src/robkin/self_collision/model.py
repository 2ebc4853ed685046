"""The self-collision model of a robot: a capsule per link, the pairs checked, the compiled check.

``SelfCollisionModel`` holds the capsules (``capsules``), the allowed-collision matrix (``acm``: the
pairs never checked, with MoveIt's reasons) and, from both, the pairs that are checked. ``collides(q)``
answers per configuration whether any checked pair of capsules touches or overlaps; ``distances(q)``
gives each checked pair's distance (negative: overlap), and ``closest(q, k)`` the k closest pairs. Both
run compiled (``robkin.compiled.collision.capsules``: the chain's frames and the segment distances
per block of configurations, blocks over every core; ``threads`` as ``Robot.fk``).

Conservative: the capsules contain the links' collision geometry, so a configuration the model calls
free is free for the meshes too (for the checked pairs); one it calls colliding may be a near miss.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..checks import check_q, check_threads
from ..errors import InputError
from .capsules import Capsule
from .revolve import PartArrays

if TYPE_CHECKING:  # pragma: no cover
    from ..robot import Robot
    from .capsules import Part
    from .exact import ExactChecker

__all__ = ["SelfCollisionModel", "DisabledPair", "LEVELS"]

#: How far ``SelfCollisionModel.collides`` goes: capsules (compiled), then the links' convex parts
#: (compiled), then the meshes (coal).
LEVELS = ("capsules", "parts", "exact")


@dataclass(frozen=True)
class DisabledPair:
    """A link pair never checked: ``reason`` 'Adjacent' (joined by one joint), 'Default' (in collision at
    the robot's home), 'Always' (in collision at every sampled configuration) or 'Never' (in collision at
    none), as MoveIt's SRDF ``<disable_collisions>`` says."""

    link1: str
    link2: str
    reason: str


@dataclass(eq=False)
class SelfCollisionModel:
    """Capsules of the links and the link pairs checked (see the module doc).

    robot : the robot (its chain moves the capsules)
    capsules : one or more per link with collision geometry (a link's consecutive)
    disabled : the allowed-collision matrix: pairs never checked
    samples : configurations the matrix was sampled at (0: given, not sampled)
    """

    robot: Robot
    capsules: list[Capsule]
    disabled: list[DisabledPair] = field(default_factory=list)
    samples: int = 0
    #: the exact check of the links' own geometry (``exact.ExactChecker``), when coal was there to build it
    exact: ExactChecker | None = None
    #: convex parts of the links (``capsules.link_parts``), the compiled test between the capsules and the
    #: exact check; None: straight from capsules to coal
    parts: list[Part] | None = None

    def __post_init__(self) -> None:
        names: list[str] = []
        for c in self.capsules:
            if c.link not in names:
                names.append(c.link)
        index = {name: k for k, name in enumerate(names)}
        of_link: list[list[int]] = [[] for _ in names]
        for k, c in enumerate(self.capsules):
            of_link[index[c.link]].append(k)
        off = {frozenset((d.link1, d.link2)) for d in self.disabled}
        links = [(i, j) for i in range(len(names)) for j in range(i + 1, len(names))
                 if frozenset((names[i], names[j])) not in off]
        # capsule pairs grouped by link pair, in the order of ``links`` (``starts``: where each group begins)
        caps_pairs = [(u, v) for i, j in links for u in of_link[i] for v in of_link[j]]
        sizes = [len(of_link[i]) * len(of_link[j]) for i, j in links]
        self._names = names
        self._index = index
        self._link_pairs = np.array(links, dtype=np.intc).reshape(-1, 2)
        self._pairs = np.array(caps_pairs, dtype=np.intc).reshape(-1, 2)
        self._starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.intp) if sizes else np.zeros(0, np.intp)
        # each link pair's capsule-pair columns, padded with its first (a link pair's distance: their minimum;
        # one fancy index and a min, much faster than np.minimum.reduceat along rows)
        width = max(sizes, default=1)
        self._groups = np.array([[s + min(k, z - 1) for k in range(width)] for s, z in zip(self._starts, sizes)],
                                dtype=np.intp).reshape(len(sizes), width)
        # each capsule's end points in its body's GJD frame at q = 0 (body 0: the base frame)
        J = self.robot.frames
        caps = np.empty((len(self.capsules), 7))
        for k, c in enumerate(self.capsules):
            inv = np.linalg.inv(J[c.body - 1]) if c.body > 0 else np.eye(4)
            caps[k, :3] = inv[:3, :3] @ c.a + inv[:3, 3]
            caps[k, 3:6] = inv[:3, :3] @ c.b + inv[:3, 3]
            caps[k, 6] = c.radius
        self._caps = caps
        self._frame = np.array([c.body for c in self.capsules], dtype=np.intc)
        # the parts' points and capsules in their bodies' frames, for ``parts_apart``
        self._parts: PartArrays | None = None
        self._maps: list[Any] | None = None     # ``pairmaps.pair_maps``, built at the first use
        self._map_args: tuple[Any, ...] | None = None   # ``_map_arrays``, built with the maps
        if self.parts and {p.link for p in self.parts} >= set(names):
            local: list[np.ndarray] = []
            of_part: list[list[int]] = [[] for _ in names]
            frame: list[int] = []
            bound: list[list[float]] = []
            for k, part in enumerate(p for p in self.parts if p.link in index):
                inv = np.linalg.inv(J[part.body - 1]) if part.body > 0 else np.eye(4)
                local.append(part.vertices @ inv[:3, :3].T + inv[:3, 3])
                bound.append([*(inv[:3, :3] @ part.a + inv[:3, 3]), *(inv[:3, :3] @ part.b + inv[:3, 3]), part.radius])
                of_part[index[part.link]].append(k)
                frame.append(part.body)
            start = np.concatenate([[0], np.cumsum([len(h) for h in local])]).astype(np.intp)
            link_start = np.concatenate([[0], np.cumsum([len(ks) for ks in of_part])]).astype(np.intp)
            link_parts = np.array([k for ks in of_part for k in ks], dtype=np.intc)
            self._parts = (np.vstack(local), start, np.array(frame, dtype=np.intc), np.array(bound), link_start,
                           link_parts)

    @property
    def links(self) -> list[str]:
        """The links with capsules, in the model's order."""
        return list(self._names)

    @property
    def pairs(self) -> list[tuple[str, str]]:
        """The checked link pairs, in the order of ``distances``' last axis."""
        return [(self._names[i], self._names[j]) for i, j in self._link_pairs]

    def with_disabled(self, disabled: Sequence[DisabledPair]) -> SelfCollisionModel:
        """The same capsules with another allowed-collision matrix (an SRDF read back, say).

        Parameters
        ----------
        disabled : sequence of DisabledPair
            The pairs never checked; both links of each must have collision geometry in this model
            (``links``), else InputError naming the link.
        """
        known = set(self._index)
        for d in disabled:
            for name in (d.link1, d.link2):
                if name not in known:
                    raise InputError(f"disable_collisions: link {name!r} has no collision geometry in this "
                                     f"robot (links: {', '.join(sorted(known))})")
        return SelfCollisionModel(self.robot, self.capsules, list(disabled), self.samples, self.exact, self.parts)

    def pair_maps(self) -> list[Any]:
        """The tabulated pairs of the 'parts' level (``pairmaps``: pairs one or two revolute joints move
        against each other, cells proven apart), built at the first call (a second or so for a UR5)."""
        if self._maps is None:
            from .pairmaps import pair_maps

            self._maps = pair_maps(self)
        return self._maps

    def _q(self, q: ArrayLike) -> tuple[np.ndarray, bool]:
        qa = np.asarray(q)
        single = qa.ndim == 1
        qa = np.ascontiguousarray(check_q(qa[None] if single else qa, self.robot.n), dtype=np.float64)
        return qa, single

    def collides(self, q: ArrayLike, *, level: str = "capsules", threads: int | None = None) -> bool | np.ndarray:
        """Whether the robot is in self collision: q (n,) -> bool, (N, n) -> (N,) bool.

        ``level`` (see ``LEVELS``):

        - ``'capsules'``: some checked pair of capsules touches or overlaps (compiled, conservative:
          False means free for the meshes; True may be a near miss);
        - ``'parts'``: where the capsules meet, the convex hulls of the links' parts (``capsules.
          link_parts``) are tested for a separating plane (compiled, GJK): still conservative, tighter;
        - ``'exact'``: what the parts leave is collided with the links' own geometry (coal,
          ``exact.ExactChecker``, a Python call per configuration): the meshes' answer. Needs coal.

        Parameters
        ----------
        q : array (n,) or (N, n)
            Joint values (rad for revolute joints, length units for prismatic ones).
        level : {'capsules', 'parts', 'exact'}
            How far the check goes (above).
        threads : int, optional
            Threads of the compiled kernels (None or 0: automatic, ``robkin.threads``; 1: this thread only).
        """
        if level not in LEVELS:
            raise InputError(f"level: {level!r} is not one of {', '.join(LEVELS)}")
        if level == "exact" and self.exact is None:
            raise InputError("level 'exact': this model has no exact check (coal was not installed when it was "
                             "built: pip install coal)")
        qa, single = self._q(q)
        t = 0 if threads is None else check_threads(threads)
        if level == "capsules":
            from ..compiled.collision.capsules import collide

            hit = collide(self.robot._chain, qa, self._caps, self._frame, self._pairs, t)
            assert hit is not None  # checked, finite, contiguous float64
            out = hit.view(np.bool_)
        else:
            out = self._refine(qa, t, level == "exact")
        return bool(out[0]) if single else out

    def _refine(self, qa: np.ndarray, threads: int, exact: bool) -> np.ndarray:
        """Levels 'parts' and 'exact' (see ``collides``): one compiled pass gives, per configuration, the
        link pairs whose capsules overlap and that no pair map clears (``capsules.overlaps``, deepest
        first); the parts' GJK test takes those, and with ``exact`` coal what it leaves."""
        from ..compiled.collision.capsules import overlaps

        link_of, link_pairs, map_of, joints, lower, width, cells, start, free = self._map_arrays()
        queries = overlaps(self.robot._chain, qa, self._caps, self._frame, self._pairs, link_of, link_pairs, map_of,
                           joints, lower, width, cells, start, free, threads)
        assert queries is not None  # checked, finite, contiguous float64
        hit = np.zeros(len(qa), dtype=bool)
        if self._parts is not None and len(queries):
            from ..compiled.collision.parts import parts_apart

            r = queries[:, 0]
            first = np.empty(len(r), dtype=bool)      # rows come in order: each configuration's first query
            first[0] = True
            np.not_equal(r[1:], r[:-1], out=first[1:])
            rows = r[first]
            local = queries.copy()
            local[:, 0] = np.cumsum(first) - 1
            frames = self.robot.frames_at(np.ascontiguousarray(qa[rows]), threads=threads or None)
            cleared = parts_apart(frames, *self._parts, local, threads).view(np.bool_)
            queries = queries[~cleared]
        if not exact:
            hit[queries[:, 0]] = True
            return hit
        assert self.exact is not None
        for r in np.unique(queries[:, 0]):
            near = [(int(u), int(v)) for u, v in queries[queries[:, 0] == r, 1:]]
            hit[r] = bool(self.exact.colliding_pairs(qa[r], near, first=True))
        return hit

    def _map_arrays(self) -> tuple[Any, ...]:
        """The arguments of ``capsules.overlaps`` after ``pairs``: each capsule pair's link pair, the link
        pairs, and the pair maps (``pair_maps``) flattened: map of each link pair (-1: none), joints,
        lower limits, cell widths, cells per joint, each map's first cell and the cells, one bit each (1:
        proven apart)."""
        if self._map_args is None:
            link_of = np.repeat(np.arange(len(self._link_pairs), dtype=np.intc),
                                np.diff(np.r_[self._starts, len(self._pairs)]).astype(np.intp)) \
                if len(self._link_pairs) else np.zeros(0, np.intc)
            maps = self.pair_maps() if self._parts is not None else []
            map_of = np.full(len(self._link_pairs), -1, dtype=np.intc)
            joints = np.full((len(maps), 2), -1, dtype=np.intc)
            lower = np.zeros((len(maps), 2))
            width = np.ones((len(maps), 2))
            start = np.zeros(len(maps), dtype=np.intp)
            cells_of = np.array([m.cells for m in maps], dtype=np.intc)
            at = 0
            for k, m in enumerate(maps):
                map_of[m.pair] = k
                joints[k, :len(m.joints)] = m.joints
                lower[k, :len(m.joints)] = m.lower
                width[k, :len(m.joints)] = m.width
                start[k] = at
                at += m.cells ** len(m.joints)
            # every map's cells one after the other, one bit each (``capsules.overlaps``)
            free = np.packbits(np.concatenate([m.free.reshape(-1) for m in maps]), bitorder="little") if maps \
                else np.zeros(0, np.uint8)
            self._map_args = (link_of, self._link_pairs, map_of, joints, lower, width, cells_of, start, free)
        return self._map_args

    def distances(self, q: ArrayLike, *, threads: int | None = None) -> np.ndarray:
        """Distance between the capsules of each checked pair (length units; negative: they overlap by
        that much): q (n,) -> (P,), (N, n) -> (N, P), in the order of ``pairs``.

        Parameters
        ----------
        q : array (n,) or (N, n)
            Joint values (rad / length units).
        threads : int, optional
            Threads of the compiled kernel (None or 0: automatic, ``robkin.threads``).
        """
        from ..compiled.collision.capsules import distances

        qa, single = self._q(q)
        t = 0 if threads is None else check_threads(threads)
        d = distances(self.robot._chain, qa, self._caps, self._frame, self._pairs, t)
        assert d is not None
        if len(self._pairs) != len(self._link_pairs):   # a link pair's distance: its nearest capsule pair's
            d = d[:, self._groups].min(axis=2) if len(self._starts) else d[:, :0]
        return d[0] if single else d

    def closest(self, q: ArrayLike, k: int = 3) -> list[tuple[str, str, float]]:
        """The ``k`` closest checked pairs at one configuration q (n,): [(link1, link2, distance)], nearest first."""
        d = self.distances(q)
        if d.ndim != 1:
            raise InputError("closest: one configuration q (n,)")
        names = self.pairs
        return [(names[i][0], names[i][1], float(d[i])) for i in np.argsort(d, kind="stable")[:max(int(k), 0)]]

