"""Type stub of the compiled module ``robkin.compiled.runtime.rigid`` (see rigid.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

def exact_poses(A: ArrayLike) -> NDArray[np.bool_]: ...
def frame_stacks(frames: ArrayLike, want_scale: bool, want_local: bool
                 ) -> tuple[NDArray[np.float64] | None, NDArray[np.float64] | None]: ...
