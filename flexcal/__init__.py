"""flexcal: turn a home-made flex-sensor glove into a calibrated instrument.

Parts (see DESIGN.md): ``flexcal.synthetic`` renders ground truth, ``flexcal.capture``
talks to the glove and reads logs, ``flexcal.vision`` measures bend angles in photos,
``flexcal.calibration`` fits the models.
"""

from importlib.metadata import PackageNotFoundError, version as _version

try:
    __version__ = _version("flexcal")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
