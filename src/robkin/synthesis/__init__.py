"""Manipulator synthesis: initial structure estimates (types A-D), metrics, and an optimiser.

- ``estimate`` / ``estimate_all``: the estimation paper's four structures that reach a target pose.
- ``structure_metrics``: eq. (48) length and Yoshikawa manipulability at q = 0.
- ``synthesize``: DH parameters that reach every pose of a task at least cost, from an estimate or a
  random start (``optimize.py``); ``sweep.run_sweep`` runs many of them in parallel.

scipy (and dask, for sweeps on a cluster) are imported only when used.
"""

from __future__ import annotations

from .estimate import KINDS, Estimate, estimate, estimate_all
from .metrics import Metrics, link_length, structure_metrics
from .optimize import SynthesisResult, Task, make_task, synthesize, synthesize_multistart

__all__ = ["KINDS", "Estimate", "estimate", "estimate_all", "Metrics", "link_length", "structure_metrics",
           "Task", "make_task", "SynthesisResult", "synthesize", "synthesize_multistart"]
