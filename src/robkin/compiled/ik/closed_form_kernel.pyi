"""Type stub of the compiled module ``robkin.compiled.ik.closed_form_kernel`` (see closed_form_kernel.pyx)."""

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..chain.fk import Chain

class ClosedFormKernel:
    n: int
    S: int
    def __init__(self, chain: Chain, limits: ArrayLike, revolute: ArrayLike, scale: float, limit_tol: float,
                 ref0: ArrayLike, S: int, work_size: int) -> None: ...
    def solve(self, targets: ArrayLike, q_ref: ArrayLike, threads: int = 0) -> tuple[NDArray[np.float64], NDArray[np.bool_],
                                                                   NDArray[np.int8], NDArray[np.float64],
                                                                   NDArray[np.bool_], int]: ...
    def nearest(self, target: object, q_ref: ArrayLike | None, tol_position: object, tol_orientation: object,
                every: bool, same_tol: float, result_type: type, method: str,
                embed: tuple[ArrayLike, ArrayLike] | None = None) -> Any: ...
