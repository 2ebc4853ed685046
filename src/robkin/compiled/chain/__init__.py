"""The kinematic chain's compiled kernels: forward kinematics and frames (``fk``, the chain of ``fk.pxd``),
Jacobians (``jacobian``), rigid-body dynamics (``dynamics``), the batch block kernels compiled portable
(``kernels``) and for AVX2 (``kernels_avx2``) with their table (``kernel_table.pxd``), and the synthesis
optimiser's standard-DH chain (``dh_chain``)."""
