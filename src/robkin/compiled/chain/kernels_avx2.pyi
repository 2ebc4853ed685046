"""Type stub of the compiled module ``robkin.compiled.chain.kernels_avx2`` (see kernels_avx2.pyx).

Never import it yourself: ``kernels`` imports it only after the CPU said it has AVX2."""

from typing import Any

#: a PyCapsule named "robkin.compiled.chain.kernels_avx2.TABLE" holding the module's BlockKernels
TABLE_CAPSULE: Any
