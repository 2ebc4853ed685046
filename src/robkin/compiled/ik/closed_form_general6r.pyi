"""Type stub of the compiled module ``robkin.compiled.ik.closed_form_general6r``
(see closed_form_general6r.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..chain.fk import Chain
from .closed_form_kernel import ClosedFormKernel

def eigenvalues(A: ArrayLike) -> NDArray[np.complex128]: ...

class General6RKernel(ClosedFormKernel):
    def __init__(self, chain: Chain, limits: ArrayLike, ref0: ArrayLike, scale: float, limit_tol: float,
                 L: ArrayLike, shift: int, reverse: bool, delta: ArrayLike) -> None: ...
    def pencil(self, T: ArrayLike) -> NDArray[np.float64] | None: ...
    def set_deflation(self, complement: ArrayLike | None) -> None: ...
