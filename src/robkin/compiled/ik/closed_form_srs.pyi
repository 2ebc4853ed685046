"""Type stub of the compiled module ``robkin.compiled.ik.closed_form_srs`` (see closed_form_srs.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .closed_form_kernel import ClosedFormKernel
from ..chain.fk import Chain

class SRSKernel(ClosedFormKernel):
    def __init__(self, chain: Chain, limits: ArrayLike, ref0: ArrayLike, scale: float, limit_tol: float,
                 axes: ArrayLike, S: ArrayLike, W0: ArrayLike, p4: ArrayLike, E0: ArrayLike, w_tool: ArrayLike,
                 R_home: ArrayLike, zref: ArrayLike, zalt: ArrayLike, A: float, B: float, C0: float) -> None: ...
    def candidates(self, targets: ArrayLike, psi: ArrayLike, q_ref: ArrayLike | None = None
                   ) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.bool_] | None, NDArray[np.int8]]: ...
