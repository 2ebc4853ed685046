"""Type stub of the compiled module ``robkin.compiled.fk`` (see fk.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

class Chain:
    n: int
    def __init__(self, L: ArrayLike, revolute: ArrayLike) -> None: ...
    def fk(self, q: object) -> NDArray[np.float64] | None: ...
    def frames(self, q: object) -> NDArray[np.float64] | None: ...
