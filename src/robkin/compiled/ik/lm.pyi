"""Type stub of the compiled module ``robkin.compiled.ik.lm`` (see lm.pyx)."""

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..chain.fk import Chain

def solve(chain: Chain, targets: ArrayLike, q0: ArrayLike, mask: ArrayLike, lower: ArrayLike,
          upper: ArrayLike, restart_lower: ArrayLike, restart_upper: ArrayLike, scale: float,
          settings: Any, seed: int, threads: int = 0, ref: ArrayLike | None = None
          ) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.int64], NDArray[np.int64],
                     NDArray[np.float64], NDArray[np.float64]]: ...
def pose_errors(chain: Chain, q: ArrayLike, targets: ArrayLike, mask: ArrayLike
                ) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
