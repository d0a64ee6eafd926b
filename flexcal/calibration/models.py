"""Physical models of the flex sensor, with their units.

Angles in degrees at every interface; radians only inside the trigonometry.
"""

from __future__ import annotations

import numpy as np

from flexcal.calibration import reference

STANDARD_GRAVITY = 9.80665        # m / s^2
SQ_INCH_M2 = 0.0254 ** 2          # one square inch in m^2
PSI_PA = 6894.757293168           # one psi in pascal


def pressure_from_mass(mass_g, contact_area_in2=reference.CONTACT_AREA_IN2):
    """Pressure of a mass resting on a pad of the given contact area.

    Returns ``(pressure_psi, pressure_kpa)``; arrays in, arrays out.
    """
    if np.any(np.asarray(contact_area_in2) <= 0):
        raise ValueError(f"contact_area_in2 must be a positive area in square inches, got {contact_area_in2!r}")
    pa = np.asarray(mass_g, float) / 1000.0 * STANDARD_GRAVITY / (np.asarray(contact_area_in2, float) * SQ_INCH_M2)
    return pa / PSI_PA, pa / 1000.0


def knuckle_pressure_psi(angle_deg, deg_per_psi=reference.ANGLE_VS_PRESSURE[0]):
    """The knuckle's pressure on the sensor at a bend angle, p = theta / 4.342 (psi).

    The reference reads the pressure experiment's slope (4.342 degrees per psi) as the
    proportionality between bend and the knuckle's pressure, ignoring the intercept.
    """
    return np.asarray(angle_deg, float) / deg_per_psi


def pressure_shape(angle_deg, deg_per_psi=reference.ANGLE_VS_PRESSURE[0]):
    """p(theta) * theta / cos((pi - theta) / 2), theta in radians inside (psi).

    The reference's eq for R_pressure divided by k. The cosine's argument is the
    half-angle alpha = (pi - theta)/2 of the tension triangle, in radians; the leading
    theta is the wrapped arc's angle, also in radians (arc length = r * theta).
    """
    th = np.deg2rad(np.asarray(angle_deg, float))
    return knuckle_pressure_psi(angle_deg, deg_per_psi) * th / np.cos((np.pi - th) / 2)


def pressure_resistance_ohm(angle_deg, k_ohm_per_psi, deg_per_psi=reference.ANGLE_VS_PRESSURE[0]):
    """R_pressure = k * p(theta) * theta / cos((pi - theta)/2), in ohm (k in ohm per psi)."""
    return k_ohm_per_psi * pressure_shape(angle_deg, deg_per_psi)
