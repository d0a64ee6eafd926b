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


# --- the reference's physics (DESIGN.md), SI units inside ---------------------------

def second_moment_m4(width_m, thickness_m):
    """Area moment of inertia of the sensor's rectangular section, I = w t^3 / 12 (m^4). (eq 2)"""
    return np.asarray(width_m, float) * np.asarray(thickness_m, float) ** 3 / 12.0


def cantilever_angle_deg(force_n, length_m, youngs_modulus_pa, width_m, thickness_m):
    """End slope of a cantilever under an end load, theta = F L^2 / (2 E I), in degrees. (eq 1)"""
    th = np.asarray(force_n, float) * np.asarray(length_m, float) ** 2 / (
        2.0 * np.asarray(youngs_modulus_pa, float) * second_moment_m4(width_m, thickness_m))
    return np.rad2deg(th)


def bending_resistance_ohm(angle_deg, resistivity_ohm_m, thickness_m, section_area_m2, r0_ohm):
    """R_bending = (rho t / A_c) theta + R0 (ohm), theta in radians inside. (eqs 3-5)

    Bending by theta stretches the conductive layer, at distance t from the neutral
    axis, by dl = t * theta; its resistance grows by rho dl / A_c.
    """
    th = np.deg2rad(np.asarray(angle_deg, float))
    return np.asarray(resistivity_ohm_m, float) * np.asarray(thickness_m, float) / np.asarray(
        section_area_m2, float) * th + np.asarray(r0_ohm, float)


def tension_n(pressure_pa, contact_area_m2, angle_deg):
    """Tension the knuckle's pressure puts in the sensor, T = p A_s / (2 cos alpha), alpha = (pi - theta)/2. (eq 6)"""
    alpha = (np.pi - np.deg2rad(np.asarray(angle_deg, float))) / 2
    return np.asarray(pressure_pa, float) * np.asarray(contact_area_m2, float) / (2 * np.cos(alpha))


def pressure_k_from_material(resistivity_ohm_m, knuckle_radius_m, length_m, width_m, youngs_modulus_pa,
                             section_area_m2):
    """k = rho r L0 w / (2 E A_c^2), converted to ohm per psi so that R_pressure = k p(theta) theta / cos alpha
    with p in psi and theta in radians. (eqs 7-8: the stretch dL = T L0 / (E A_c) with A_s = w r theta)"""
    k_ohm_per_pa = (np.asarray(resistivity_ohm_m, float) * np.asarray(knuckle_radius_m, float)
                    * np.asarray(length_m, float) * np.asarray(width_m, float)
                    / (2 * np.asarray(youngs_modulus_pa, float) * np.asarray(section_area_m2, float) ** 2))
    return k_ohm_per_pa * PSI_PA


def physical_resistance_ohm(angle_deg, offset_ohm, slope_ohm_per_deg, k_ohm_per_psi,
                            deg_per_psi=reference.ANGLE_VS_PRESSURE[0]):
    """The final model (eq 20): R_total = R_bending + R_pressure, with R_bending = slope * theta + offset."""
    a = np.asarray(angle_deg, float)
    return offset_ohm + slope_ohm_per_deg * a + pressure_resistance_ohm(a, k_ohm_per_psi, deg_per_psi)
