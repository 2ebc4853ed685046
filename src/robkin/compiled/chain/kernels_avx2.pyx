# cython: language_level=3
"""The batch block kernels built for AVX2 (setup.py compiles this module alone with -mavx2).

Never import it yourself: everything in it, its initialisation included, may use AVX2 instructions, so
``kernels.pyx`` imports it only after the CPU said it has AVX2. ``TABLE`` is a capsule holding its
``BlockKernels`` (``kernel_table.pxd``).
"""

from cpython.pycapsule cimport PyCapsule_New

include "kernel_bodies.pxi"

TABLE_CAPSULE = PyCapsule_New(<void*>&TABLE, b"robkin.compiled.chain.kernels_avx2.TABLE", NULL)
