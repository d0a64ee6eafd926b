"""Bend-angle measurement in side-view photos."""
