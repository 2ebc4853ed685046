"""Type stub of the compiled module ``robkin.compiled.ik.limits`` (see limits.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

def wrap(Q: ArrayLike, lower: ArrayLike, upper: ArrayLike, revolute: ArrayLike, ref: ArrayLike,
         tol: float) -> tuple[NDArray[np.float64], NDArray[np.bool_]]: ...
