"""The parts of ``robkin calibrate`` beyond the calibration itself, one module each.

- ``plan``: ``--plan N``: the options of a pose plan and its run (which configurations to measure,
  ``robkin.calibration.planning_poses``).
- ``frames``: the frames the calibrated robot is written with (``--keep-frames``: the nominal world and
  flange kept, the marker as a link of its own).
- ``controller``: the outputs for a robot controller (``--offsets``: joint zero offsets, ``--table``: the
  table in the source's convention, ``--filter``: the joint values that reach targets).
"""
