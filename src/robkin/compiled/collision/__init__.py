"""Collision kernels: batch self-collision of capsule models after the chain's batch frames (``capsules``),
and the separating-plane test of links' convex parts (``parts``)."""
