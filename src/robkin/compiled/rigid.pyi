"""Type stub of the compiled module ``robkin.compiled.rigid`` (see rigid.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

def exact_poses(A: ArrayLike) -> NDArray[np.bool_]: ...
