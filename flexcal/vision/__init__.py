"""Bend-angle measurement in side-view photos: arrays in, measurements out (no file IO)."""

from flexcal.vision.angle import measure_angle
from flexcal.vision.markers import find_markers
from flexcal.vision.measurement import AngleMeasurement, Arm, as_bgr8
from flexcal.vision.overlay import contact_sheet, draw_overlay

__all__ = ["AngleMeasurement", "Arm", "as_bgr8", "contact_sheet", "draw_overlay", "find_markers", "measure_angle"]
