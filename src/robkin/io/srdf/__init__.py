"""SRDF (MoveIt's Semantic Robot Description Format): the allowed-collision matrix.

- ``srdf``: ``srdf_text(robot_name, disabled)`` writes ``<disable_collisions link1= link2= reason=/>``
  lines; ``read_srdf(path)`` reads them back (other SRDF elements are skipped).

An io package: it knows the file format, never the self-collision model it serves.
"""

from __future__ import annotations

from ...lazy_exports import lazy_exports

__all__ = ["srdf_text", "read_srdf", "parse_srdf", "REASONS"]

__getattr__, __dir__ = lazy_exports(__name__, globals(), {
    "srdf_text": ".srdf", "read_srdf": ".srdf", "parse_srdf": ".srdf", "REASONS": ".srdf"})
