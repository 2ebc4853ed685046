"""Type stub of the compiled module ``robkin.compiled.chain.dh_chain`` (see dh_chain.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

def dh_frames(a: ArrayLike, d: ArrayLike, alpha: ArrayLike, theta: ArrayLike
              ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...
def dh_volumes(a: ArrayLike, d: ArrayLike, alpha: ArrayLike, theta: ArrayLike, length: ArrayLike,
               pose: bool) -> NDArray[np.float64]: ...
