"""Type stub of the compiled module ``robkin.compiled.collision.capsules`` (see capsules.pyx)."""

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robkin.compiled.chain.fk import Chain

def collide(chain: Chain, q: object, caps: ArrayLike, frame: ArrayLike, pairs: ArrayLike,
            threads: int = 0) -> NDArray[np.uint8] | None: ...
def distances(chain: Chain, q: object, caps: ArrayLike, frame: ArrayLike, pairs: ArrayLike,
              threads: int = 0) -> NDArray[np.float64] | None: ...
def segment_distance(p1: ArrayLike, q1: ArrayLike, p2: ArrayLike, q2: ArrayLike) -> float: ...
def overlaps(chain: Chain, q: object, caps: ArrayLike, frame: ArrayLike, pairs: ArrayLike, link_of: ArrayLike,
             link_pairs: ArrayLike, map_of: ArrayLike, map_joints: ArrayLike, map_lower: ArrayLike,
             map_width: ArrayLike, map_cells: ArrayLike, map_start: ArrayLike, map_free: ArrayLike,
             threads: int = 0) -> NDArray[np.intc] | None: ...
