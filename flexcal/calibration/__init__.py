"""Pairing photos with readings, fitting and validating the calibration models.

``load(path)`` reads a calibration.json (docs/calibration-json.md).
"""

from flexcal.calibration.export import Calibration, load

__all__ = ["Calibration", "load"]
