"""Type stub of the compiled module ``robkin.compiled.collision.parts`` (see parts.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

def parts_apart(frames: ArrayLike, verts: ArrayLike, start: ArrayLike, frame: ArrayLike, bound: ArrayLike,
                link_start: ArrayLike, link_parts: ArrayLike, queries: ArrayLike,
                threads: int = 0, margin: float = 0.0) -> NDArray[np.uint8]: ...
