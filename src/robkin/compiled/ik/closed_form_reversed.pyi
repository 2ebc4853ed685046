"""Type stub of the compiled module ``robkin.compiled.ik.closed_form_reversed`` (see closed_form_reversed.pyx)."""

from numpy.typing import ArrayLike

from ..chain.fk import Chain
from .closed_form_kernel import ClosedFormKernel

class ReversedKernel(ClosedFormKernel):
    def __init__(self, chain: Chain, limits: ArrayLike, revolute: ArrayLike, scale: float, limit_tol: float,
                 ref0: ArrayLike, inner: ClosedFormKernel) -> None: ...
