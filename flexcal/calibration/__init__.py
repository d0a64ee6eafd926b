"""Pairing photos with readings, fitting and validating the calibration models."""
