"""Type stub of the compiled module ``robkin.compiled.chain.jacobian`` (see jacobian.pyx)."""

import numpy as np
from numpy.typing import NDArray

from .fk import Chain

GEOMETRIC: int
SPACE: int
BODY: int

def jacobian(chain: Chain, q: object, kind: int, threads: int = 0, out: object = None) -> NDArray[np.float64] | None: ...
def volumes(J: object, threads: int = 0) -> NDArray[np.float64]: ...
def manipulability(chain: Chain, q: object, first: int, rows: int, threads: int = 0) -> NDArray[np.float64] | None: ...
