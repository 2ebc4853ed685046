"""The numbers and words every reader of a robot description shares, in Python so that the compiled
scanners (``urdf_scan``, ``attribute_numbers``) and the Python readers (``io.files.numbers``,
``io.trees.model``) take them from one place, and a reader that needs only a bound loads no extension."""

__all__ = ["MAX_ABS", "MAX_JOINTS", "NO_LIMIT", "SUPPORTED_TYPES", "UNSUPPORTED_TYPES"]

#: Largest magnitude of any number in a robot description. Norms and products of a few such numbers
#: must stay finite in float64 (1e100 squared is 1e200), so an absurd value is refused where it is
#: read, naming its field, instead of overflowing later in a computed frame that the user never typed.
MAX_ABS = 1e100
#: Most joints of a robot read from any input (document, table, pasted rows, URDF/MJCF/SDF chain). Real
#: arms have 6-7, snakes and long test chains 1000; reading costs ~0.4 ms and ~6 kB per joint, so the cap
#: bounds one read to seconds and ~100 MB (200 000 pasted rows took > 60 s and 1.2 GB).
MAX_JOINTS = 10_000
#: URDF has no way to say "no limit" on a prismatic joint (urdfdom, and so pinocchio, refuse ``inf``),
#: so a missing limit is written as +-NO_LIMIT and a limit at least this large is read as none. No real
#: joint travels 1e10 m or rad; the value is finite in float32 too (MuJoCo's limits).
NO_LIMIT = 1e10
#: URDF joint kinds a chain is read from, and those robkin recognises but refuses on a chain.
SUPPORTED_TYPES = ("revolute", "continuous", "prismatic", "fixed")
UNSUPPORTED_TYPES = ("floating", "planar")
