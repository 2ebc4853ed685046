"""The compiled kinematics core: the hot loops of robkin, in Cython, built at install time.

Every numerical hot loop lives here once (forward kinematics single and batch, frames along the chain,
Jacobians, the Levenberg-Marquardt iteration, the closed-form solvers, frame placement for the
conversions). The Python modules around it validate input once and call in; there is no second
numpy copy of the same algorithm.

The modules are grouped by topic into sub-packages:

- ``chain``: the kinematic chain's kernels: forward kinematics, Jacobians, dynamics, the batch block
  kernels (portable and AVX2 builds, their table) and the synthesis optimiser's DH chain;
- ``ik``: inverse kinematics: the closed-form kernels, Levenberg-Marquardt, Newton polish of branches,
  the choice among solutions, joint limits, and their C helpers (subproblems, elimination, Newton);
- ``conversions``: between representations: DH / MDH frame placement and tables, the readers' poses as
  twelve floats;
- ``scanners``: the robot-file scans (URDF, SDF) over the standard library's expat, and attribute numbers;
- ``runtime``: what the others share: threads, small dense and fixed-size linear algebra, sin/cos,
  NumPy-order arithmetic, the exact-rigid-transform test and the bounded least-squares solver.

Modules are plain extension modules (``robkin.compiled.<topic>.<name>``, e.g.
``robkin.compiled.chain.fk``); importing one costs well under a millisecond, and nothing here is
imported by ``import robkin``. Each has a type stub (``<name>.pyi``) beside it. C headers are named by
their path under this folder (``cdef extern from "runtime/sincos.h"``), which setup.py puts on every
extension's include path.
"""
