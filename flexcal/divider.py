"""The glove's voltage divider: resistance <-> ADC counts, and the factory angle mapping.

One place for the conventions shared by the firmware, the sensor simulator and the
log reader. Wiring (firmware/README.md): the fixed resistor goes from Vref to the
analog pin and the flex sensor from the pin to ground, so the pin voltage rises with
the sensor's resistance::

    V_pin = V_ref * R_flex / (R_flex + R_fixed)
    adc   = floor(V_pin / V_ref * 2**bits)            (clipped to 0 ... 2**bits - 1)
    R_flex = R_fixed * (adc + 0.5) / (2**bits - adc - 0.5)   (mid-step estimate)

With oversampling, ``adc`` is the mean of several conversions and may be fractional.
The reference voltage cancels out of the ratio; it is kept as a named parameter
because the firmware reports it and the ADC-only logs of other sketches need it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Factory mapping of the reference experiment (eq 16): R = 577.9 * angle + 31 250 ohm.
FACTORY_SLOPE_OHM_PER_DEG = 577.9
FACTORY_OFFSET_OHM = 31_250.0


@dataclass(frozen=True)
class Divider:
    """A voltage divider with the flex sensor on the low side.

    Parameters
    ----------
    r_fixed_ohm : float
        The fixed resistor between V_ref and the analog pin, in ohm.
    vref_v : float
        ADC reference voltage, in volt.
    adc_bits : int
        ADC resolution (10 on an Arduino Uno).
    """

    r_fixed_ohm: float = 47_000.0
    vref_v: float = 5.0
    adc_bits: int = 10

    def __post_init__(self):
        if not np.isfinite(self.r_fixed_ohm) or self.r_fixed_ohm <= 0:
            raise ValueError(f"r_fixed_ohm must be a positive resistance in ohm, got {self.r_fixed_ohm!r}")
        if not np.isfinite(self.vref_v) or self.vref_v <= 0:
            raise ValueError(f"vref_v must be a positive voltage, got {self.vref_v!r}")
        if int(self.adc_bits) != self.adc_bits or not 1 <= self.adc_bits <= 24:
            raise ValueError(f"adc_bits must be an integer from 1 to 24, got {self.adc_bits!r}")

    @property
    def full_scale(self) -> int:
        """Number of ADC steps, 2**bits (1024 for 10 bits)."""
        return 2 ** int(self.adc_bits)

    def adc_from_resistance(self, resistance_ohm):
        """Ideal (un-quantised) ADC reading for a sensor resistance; array in, array out."""
        r = np.asarray(resistance_ohm, dtype=float)
        return self.full_scale * r / (r + self.r_fixed_ohm)

    def quantise(self, adc):
        """What one conversion returns: floor, clipped to the ADC's range."""
        return np.clip(np.floor(np.asarray(adc, dtype=float)), 0, self.full_scale - 1)

    def resistance_from_adc(self, adc):
        """Sensor resistance in ohm from a (possibly averaged) ADC reading.

        Readings at a rail (0 or full scale - 1) mean a shorted or open sensor and
        give NaN rather than a number that looks valid.
        """
        a = np.asarray(adc, dtype=float)
        top = self.full_scale - 1
        with np.errstate(divide="ignore", invalid="ignore"):
            r = self.r_fixed_ohm * (a + 0.5) / (self.full_scale - a - 0.5)
        return np.where((a <= 0) | (a >= top) | ~np.isfinite(a), np.nan, r)

    def banner(self) -> str:
        """The divider line of the firmware banner (parsed back by ``from_banner``)."""
        return (f"divider: r_fixed_ohm={self.r_fixed_ohm:g} vref_v={self.vref_v:g} "
                f"adc_bits={int(self.adc_bits)} flex=low-side")

    @classmethod
    def from_banner(cls, text: str) -> "Divider | None":
        """Read the divider parameters from a banner line; None when the line has none."""
        import re

        found = dict(re.findall(r"(r_fixed_ohm|vref_v|adc_bits)\s*=\s*([0-9.eE+-]+)", text))
        if "r_fixed_ohm" not in found:
            return None
        return cls(r_fixed_ohm=float(found["r_fixed_ohm"]),
                   vref_v=float(found.get("vref_v", 5.0)),
                   adc_bits=int(float(found.get("adc_bits", 10))))


def factory_angle_deg(resistance_ohm):
    """The firmware's factory mapping, angle = (R - 31 250) / 577.9, in degrees."""
    r = np.asarray(resistance_ohm, dtype=float)
    return (r - FACTORY_OFFSET_OHM) / FACTORY_SLOPE_OHM_PER_DEG
