"""Type stub of the compiled module ``robkin.compiled.runtime.box_lsq`` (see box_lsq.pyx)."""

from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

MESSAGES: dict[int, str]

def solve(fun: Callable[[NDArray[np.float64]], ArrayLike], jac: Callable[[NDArray[np.float64]], ArrayLike],
          x0: ArrayLike, lower: ArrayLike, upper: ArrayLike, ftol: float = 0.0, xtol: float = 0.0,
          gtol: float = 0.0, rtol: float = 0.0, max_nfev: int = 1000
          ) -> tuple[NDArray[np.float64], float, int, int, int]: ...
