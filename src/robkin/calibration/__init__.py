"""Kinematic calibration: identify the real robot from measured tool points (and orientations).

- ``calibrate(robot, q, positions, orientations=None, ...)`` -> ``CalibrationResult`` (``solve``)
- ``diagnose(robot, q, positions, ...)``: how far a model is from measurements, and which joint or
  parameter explains most of it (``robkin check MODEL MEASUREMENTS``, ``diagnosis``)
- ``read_measurements`` / ``write_measurements_csv``: the measurement files (``measurements``)
- ``simulate``: a perturbed robot and its measurements, to plan a campaign (``simulation``)
- ``plan_poses``: which configurations to measure (D-optimal; ``planning_poses``, ``planning``)
- ``iso9283``: ISO 9283 pose accuracy and repeatability per commanded pose (``iso9283``)
- ``fk_compliant``: the tool pose of a robot whose joints bend under gravity and a payload (``compliance``)

Modules: ``parameters`` (error models and their Jacobian), ``identifiability`` (which parameters the
poses determine), ``solve`` (the calibration, step by step), ``inputs`` (its checked inputs), ``start``
(the starting base and marker), ``fit`` (the robust bounded fit), ``report``, ``diagnosis``,
``measurements``, ``simulation``, ``planning`` (the exchange algorithm), ``planning_poses`` (its candidates
and plan), ``iso9283``, ``compliance`` (joint stiffness: holding torques, deflected joint values).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy_exports import lazy_exports

__all__ = ["calibrate", "CalibrationResult", "diagnose", "Diagnosis", "read_measurements",
           "write_measurements_csv", "Measurements", "simulate", "Simulation", "plan_poses", "Plan", "iso9283",
           "Iso9283Report", "fk_compliant"]

__getattr__, __dir__ = lazy_exports(__name__, globals(), {
    "calibrate": ".solve", "CalibrationResult": ".report", "diagnose": ".diagnosis", "Diagnosis": ".diagnosis",
    "read_measurements": ".measurements", "write_measurements_csv": ".measurements",
    "Measurements": ".measurements", "simulate": ".simulation", "Simulation": ".simulation",
    "plan_poses": ".planning_poses", "Plan": ".planning_poses", "iso9283": ".iso9283", "Iso9283Report": ".iso9283",
    "fk_compliant": ".compliance"})

if TYPE_CHECKING:  # pragma: no cover
    from .compliance import fk_compliant
    from .diagnosis import Diagnosis, diagnose
    from .iso9283 import Iso9283Report, iso9283
    from .measurements import Measurements, read_measurements, write_measurements_csv
    from .planning_poses import Plan, plan_poses
    from .report import CalibrationResult
    from .simulation import Simulation, simulate
    from .solve import calibrate
