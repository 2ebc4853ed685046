"""Kinematic calibration: identify the real robot from measured tool points (and orientations).

- ``calibrate(robot, q, positions, orientations=None, ...)`` -> ``CalibrationResult`` (``solve``)
- ``diagnose(robot, q, positions, ...)``: how far a model is from measurements, and which joint or
  parameter explains most of it (``robkin check MODEL MEASUREMENTS``, ``diagnosis``)
- ``read_measurements`` / ``write_measurements_csv``: the measurement files (``measurements``)
- ``simulate``: a perturbed robot and its measurements, to plan a campaign (``simulation``)

Modules: ``parameters`` (error models and their Jacobian), ``identifiability`` (which parameters the
poses determine), ``solve`` (the calibration, step by step), ``inputs`` (its checked inputs), ``start``
(the starting base and marker), ``fit`` (the robust bounded fit), ``report``, ``diagnosis``,
``measurements``, ``simulation``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy_exports import lazy_exports

__all__ = ["calibrate", "CalibrationResult", "diagnose", "Diagnosis", "read_measurements",
           "write_measurements_csv", "Measurements", "simulate", "Simulation"]

__getattr__, __dir__ = lazy_exports(__name__, globals(), {
    "calibrate": ".solve", "CalibrationResult": ".report", "diagnose": ".diagnosis", "Diagnosis": ".diagnosis",
    "read_measurements": ".measurements", "write_measurements_csv": ".measurements",
    "Measurements": ".measurements", "simulate": ".simulation", "Simulation": ".simulation"})

if TYPE_CHECKING:  # pragma: no cover
    from .diagnosis import Diagnosis, diagnose
    from .measurements import Measurements, read_measurements, write_measurements_csv
    from .report import CalibrationResult
    from .simulation import Simulation, simulate
    from .solve import calibrate
