# cython: language_level=3
"""The batch block kernels' table chosen at import (``kernels.pyx``)."""

from robkin.compiled.chain.kernel_table cimport BlockKernels

cdef const BlockKernels* active_kernels() noexcept nogil
