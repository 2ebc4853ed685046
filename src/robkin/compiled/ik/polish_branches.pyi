"""Type stub of the compiled module ``robkin.compiled.ik.polish_branches`` (see polish_branches.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..chain.fk import Chain

def polish(chain: Chain, Q: NDArray[np.float64], valid: NDArray[np.bool_], targets: ArrayLike, scale: float,
           threads: int = 0) -> None: ...
