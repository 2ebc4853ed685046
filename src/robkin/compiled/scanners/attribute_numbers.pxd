"""C-level entry points of ``attribute_numbers`` (cimported by ``urdf_scan``)."""

cpdef tuple numbers(text, Py_ssize_t count, where, what, tuple default)
cpdef object number(text, where, what, bint infinite_ok=*)
