"""The reference experiment's published fits (DESIGN.md), the numbers flexcal reproduces.

Angles in degrees, resistances in ohm, pressures in psi.
"""

#: eq 15, resistance vs firmware angle, first setup: R = 581 theta + 31 130
EQ15 = (581.0, 31_130.0)
#: eq 16, resistance vs firmware (measured) angle: the factory mapping
EQ16 = (577.9, 31_250.0)
#: eq 17, resistance vs photo (actual) angle
EQ17 = (587.1, 34_400.0)
#: eq 18, error = (17) - (16)
EQ18 = (9.2, 3_150.0)
#: pressure experiment, angle vs pressure: theta = 4.342 p + 25.39
ANGLE_VS_PRESSURE = (4.342, 25.39)
#: pressure experiment, resistance vs pressure: R = 2540 p + 45 880
RESISTANCE_VS_PRESSURE = (2_540.0, 45_880.0)
#: eq 19, ratio of the two pressure slopes: R_pressure = 585 theta (ohm per degree)
EQ19_SLOPE = 585.0
#: contact area of the foam pad in the pressure experiment, square inches
CONTACT_AREA_IN2 = 0.05
#: masses of the pressure experiment, grams, and its repeats
PRESSURE_MASSES_G = (20.0, 50.0, 100.0, 200.0)
PRESSURE_REPEATS = 5
