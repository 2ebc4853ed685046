"""Type stub of the compiled module ``robkin.compiled.ik.closed_form_pieper`` (see closed_form_pieper.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..chain.fk import Chain
from .closed_form_kernel import ClosedFormKernel

class PieperKernel(ClosedFormKernel):
    def __init__(self, chain: Chain, limits: ArrayLike, ref0: ArrayLike, scale: float, limit_tol: float,
                 L: ArrayLike, w0: ArrayLike, R_M: ArrayLike, z: ArrayLike, x6: ArrayLike,
                 delta: ArrayLike) -> None: ...

def chain_tool(La: ArrayLike) -> NDArray[np.float64]: ...
