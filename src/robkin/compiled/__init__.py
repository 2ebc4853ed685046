"""The compiled kinematics core: the hot loops of robkin, in Cython, built at install time.

Every numerical hot loop lives here once (forward kinematics single and batch, frames along the chain,
Jacobians, the Levenberg-Marquardt iteration, the closed-form solvers, frame placement for the
conversions). The Python modules around it validate input once and call in; there is no second
numpy copy of the same algorithm.

Modules are plain extension modules (``robkin.compiled.<name>``); importing one costs well under a
millisecond, and nothing here is imported by ``import robkin``.
"""
