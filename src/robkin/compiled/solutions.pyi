"""Type stub of the compiled module ``robkin.compiled.solutions`` (see solutions.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

def distinct_sorted(Q: ArrayLike, ref: ArrayLike, scale: ArrayLike, tol: float) -> NDArray[np.float64]: ...
