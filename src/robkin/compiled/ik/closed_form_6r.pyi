"""Type stub of the compiled module ``robkin.compiled.ik.closed_form_6r`` (see closed_form_6r.pyx)."""

from numpy.typing import ArrayLike

from ..chain.fk import Chain
from .closed_form_kernel import ClosedFormKernel

NEAR_SINGULAR: float

class _Kernel6R(ClosedFormKernel):
    def __init__(self, chain: Chain, ref0: ArrayLike, z: ArrayLike, c: ArrayLike, w_tool: ArrayLike,
                 R_M: ArrayLike, x6: ArrayLike, e1: ArrayLike, e2: ArrayLike, a: float, b: float, C2: complex,
                 scale: float, limits: ArrayLike, limit_tol: float) -> None: ...

class SphericalWristKernel(_Kernel6R):
    def __init__(self, chain: Chain, ref0: ArrayLike, z: ArrayLike, c: ArrayLike, w_tool: ArrayLike,
                 R_M: ArrayLike, x6: ArrayLike, e1: ArrayLike, e2: ArrayLike, a: float, b: float, C2: complex,
                 scale: float, limits: ArrayLike, limit_tol: float, k: float, sigma3: float) -> None: ...

class ThreeParallelKernel(_Kernel6R):
    def __init__(self, chain: Chain, ref0: ArrayLike, z: ArrayLike, c: ArrayLike, w_tool: ArrayLike,
                 R_M: ArrayLike, x6: ArrayLike, e1: ArrayLike, e2: ArrayLike, a: float, b: float, C2: complex,
                 scale: float, limits: ArrayLike, limit_tol: float, w: ArrayLike, sigma: ArrayLike,
                 M_inv: ArrayLike) -> None: ...
