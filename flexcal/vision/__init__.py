"""Bend-angle measurement in side-view photos: arrays in, measurements out (no file IO)."""

from flexcal.vision.angle import AngleMeasurement, Arm, as_bgr8, find_markers, measure_angle
from flexcal.vision.overlay import contact_sheet, draw_overlay

__all__ = ["AngleMeasurement", "Arm", "as_bgr8", "contact_sheet", "draw_overlay", "find_markers", "measure_angle"]
