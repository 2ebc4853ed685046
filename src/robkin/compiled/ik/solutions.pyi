"""Type stub of the compiled module ``robkin.compiled.ik.solutions`` (see solutions.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..chain.fk import Chain

def distinct_sorted(Q: ArrayLike, ref: ArrayLike, scale: ArrayLike, tol: float) -> NDArray[np.float64]: ...

def nearest_verified(chain: Chain, Q: ArrayLike, valid: ArrayLike, targets: ArrayLike, q_ref: ArrayLike,
                     limits: ArrayLike, length_unit: float, tol_position: float, tol_orientation: float,
                     limit_tol: float, every: bool, same_tol: float = 0.0, threads: int = 0
                     ) -> tuple[NDArray[np.float64], NDArray[np.bool_], list[NDArray[np.float64]] | None,
                                NDArray[np.float64], NDArray[np.float64], int]: ...
