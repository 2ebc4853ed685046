"""Type stub of the compiled module ``robkin.compiled.ik.closed_form_scara`` (see closed_form_scara.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..chain.fk import Chain
from .closed_form_kernel import ClosedFormKernel

ORIENTATION_SLACK: float

def split_travel(h: ArrayLike, s: ArrayLike, ref: ArrayLike, lo: ArrayLike,
                 hi: ArrayLike) -> NDArray[np.float64]: ...

class ScaraKernel(ClosedFormKernel):
    def __init__(self, chain: Chain, ref0: ArrayLike, u: ArrayLike, e1: ArrayLike, e2: ArrayLike, R_M: ArrayLike,
                 p_M: ArrayLike, point_in_tool: ArrayLike, a: float, b: float, C1: complex, scale: float,
                 ridx: ArrayLike, pidx: ArrayLike, sigma: ArrayLike, s: ArrayLike, limits: ArrayLike,
                 revolute: ArrayLike, limit_tol: float) -> None: ...
