"""The parts of ``robkin calibrate``: the frames its calibrated robot is written with, and the outputs
for a robot controller (joint offsets, the table in the source's convention, filtered targets)."""
