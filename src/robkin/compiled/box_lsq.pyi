"""Type stub of the compiled module ``robkin.compiled.box_lsq`` (see box_lsq.pyx)."""

from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

MESSAGES: dict[int, str]

def solve(fun: Callable[[NDArray[np.float64]], ArrayLike], jac: Callable[[NDArray[np.float64]], ArrayLike],
          x0: ArrayLike, lower: ArrayLike, upper: ArrayLike, ftol: float = ..., xtol: float = ...,
          gtol: float = ..., rtol: float = ..., max_nfev: int = ...
          ) -> tuple[NDArray[np.float64], float, int, int, int]: ...
