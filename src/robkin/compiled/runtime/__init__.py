"""What the other compiled modules share: threads (``threads``, with ``thread_placement.h``), small
linear algebra (``linalg.pxd`` fixed-size, ``dense.pxd`` any size), sin/cos of arrays (``sincos.h``),
arithmetic in NumPy's order (``numpy_order.pxd``), the exact-rigid-transform test (``rigid``) and the
bounded least-squares solver (``box_lsq``)."""
