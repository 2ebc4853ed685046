"""Type stub of the compiled module ``robkin.compiled.chain.dynamics`` (see dynamics.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

class ChainDynamics:
    n: int
    def __init__(self, L: ArrayLike, revolute: ArrayLike, mass: ArrayLike, com: ArrayLike,
                 inertia: ArrayLike) -> None: ...
    def inverse_dynamics(self, q: object, qd: object, qdd: object, gravity: ArrayLike,
                         threads: int = 0) -> NDArray[np.float64] | None: ...
    def mass_matrix(self, q: object, threads: int = 0) -> NDArray[np.float64] | None: ...
