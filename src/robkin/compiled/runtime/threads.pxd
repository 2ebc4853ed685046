# cython: language_level=3
"""How many threads a batch kernel uses (see threads.pyx)."""

cdef int batch_threads(int requested, Py_ssize_t units, Py_ssize_t min_units) noexcept nogil
