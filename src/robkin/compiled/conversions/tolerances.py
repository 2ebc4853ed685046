"""The tolerances of the frame placement and of rounding-noise snapping, in Python so that the compiled
kernel (``frames``) and the Python representations (``representations.frames``, ``representations.rounding``)
take them from one place without importing each other. (The kernel reads them once, when imported.)"""

__all__ = ["KEEP_TOL", "TIE_TOL", "SNAP_WINDOW", "SNAP_BUDGET"]

#: A given frame is kept only if it satisfies the convention to rounding noise: the DH parameters read
#: back from it then reproduce it to ~1e-12 relative, well inside the 1e-9 FK agreement we promise.
KEEP_TOL = 1e-12
#: |cos theta| below which theta is taken as +-pi/2 and the tie-break (theta = +pi/2) applies; wider
#: than rounding noise (~1e-16) so exact right angles computed through products resolve consistently.
TIE_TOL = 1e-9
#: Only values this close (radians, or relative to the robot's size for lengths) to a round one are
#: candidates for snapping: far above the rounding noise of the frame algebra (~1e-15 relative) and of
#: inputs written with 11 decimals (URDF files commonly write pi/2 as 1.57079632679, 4.9e-12 off), far
#: below any parameter a designer means (the budget below decides in the end).
SNAP_WINDOW = 1e-9
#: The FK change that snapping may cause in total, relative to the robot's size: 1e-12 is the
#: agreement promised for exact conversions, three orders above float64 rounding of a chain.
SNAP_BUDGET = 1e-12
