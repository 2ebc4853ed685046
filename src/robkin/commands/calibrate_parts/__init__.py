"""The parts of ``robkin calibrate`` beyond the calibration itself, one module each.

- ``plan``: ``--plan N``: the options of a pose plan and its run (which configurations to measure,
  ``robkin.calibration.planning_poses``).
"""
