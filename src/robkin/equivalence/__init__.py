"""Are two descriptions the same robot (``robkin check A B``)? If not, which joint differs first, and how.

- ``comparison``: ``compare(a, b)`` and its result ``Comparison``, the joint mapping ``JointMatch``;
- ``walk``: the joint-by-joint search for a joint mapping q_A = s q_B + delta;
- ``attribution``: which joint to name when there is none: the walk's, or the first axis line that moved;
- ``report``: the comparison as text (``str(comparison)``, ``robkin check``);
- ``params``: past the first difference, the parameters that differ, as the same kind of table.
"""

from __future__ import annotations

from .comparison import DEFAULT_TOL, Comparison, JointMatch, compare

__all__ = ["JointMatch", "Comparison", "compare", "DEFAULT_TOL"]
