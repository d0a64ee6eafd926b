"""Resistance -> corrected angle: the inverse mappings a calibration produces.

Three mappings share one interface (``angle_deg(resistance_ohm)``, a valid range,
``to_dict``/``from_dict``): the firmware's factory line, the direct empirical fit
(inverse of eq 17) and the physical model (bending line + knuckle pressure, eq 20,
inverted numerically: it is monotonic over the calibrated range).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexcal.calibration import reference
from flexcal.calibration.models import physical_resistance_ohm
from flexcal.divider import FACTORY_OFFSET_OHM, FACTORY_SLOPE_OHM_PER_DEG


class OutOfRange(ValueError):
    """A reading outside the calibrated resistance range."""


@dataclass(frozen=True)
class LinearMapping:
    """R = slope * angle + offset, inverted: angle = (R - offset) / slope.

    ``angle_range_deg`` is where the mapping is valid (None: everywhere, as the
    firmware's factory line claims).
    """

    slope_ohm_per_deg: float
    offset_ohm: float
    angle_range_deg: tuple | None = (0.0, 90.0)
    kind: str = "linear"

    def resistance_ohm(self, angle_deg):
        return self.slope_ohm_per_deg * np.asarray(angle_deg, float) + self.offset_ohm

    def _invert(self, r):
        return (r - self.offset_ohm) / self.slope_ohm_per_deg

    def to_dict(self) -> dict:
        return {"kind": self.kind, "form": "angle_deg = (resistance_ohm - offset_ohm) / slope_ohm_per_deg",
                "slope_ohm_per_deg": self.slope_ohm_per_deg, "offset_ohm": self.offset_ohm,
                **self._ranges()}

    def _ranges(self) -> dict:
        if self.angle_range_deg is None:
            return {"angle_range_deg": None, "resistance_range_ohm": None}
        return {"angle_range_deg": list(self.angle_range_deg), "resistance_range_ohm": list(self.resistance_range_ohm)}

    @property
    def resistance_range_ohm(self):
        if self.angle_range_deg is None:
            return (-np.inf, np.inf)
        lo, hi = self.resistance_ohm(np.array(self.angle_range_deg))
        return (float(min(lo, hi)), float(max(lo, hi)))

    def angle_deg(self, resistance_ohm, *, extrapolate: bool = False):
        """Corrected angle (deg) for resistances (ohm); NaN in, NaN out.

        Outside the calibrated resistance range raises ``OutOfRange`` unless ``extrapolate``.
        """
        r = np.asarray(resistance_ohm, float)
        lo, hi = self.resistance_range_ohm
        outside = np.isfinite(r) & ((r < lo) | (r > hi))
        if outside.any() and not extrapolate:
            first = int(np.flatnonzero(outside.ravel())[0])
            raise OutOfRange(f"{int(outside.sum())} reading(s) outside the calibrated range {lo:.0f}...{hi:.0f} ohm "
                             f"(first: {r.ravel()[first]:.0f} ohm at row {first + 1})")
        return self._invert(r)


@dataclass(frozen=True)
class PhysicalMapping(LinearMapping):
    """R = offset + slope * angle + k * p(angle) * angle / cos((pi - angle)/2), inverted numerically."""

    pressure_k_ohm_per_psi: float = 0.0
    deg_per_psi: float = reference.ANGLE_VS_PRESSURE[0]
    kind: str = "physical"

    def resistance_ohm(self, angle_deg):
        return physical_resistance_ohm(angle_deg, self.offset_ohm, self.slope_ohm_per_deg,
                                       self.pressure_k_ohm_per_psi, self.deg_per_psi)

    def _grid(self):
        lo, hi = self.angle_range_deg
        span = hi - lo
        a = np.linspace(max(-45.0, lo - span), min(175.0, hi + span), 4001)
        return a, self.resistance_ohm(a)

    def _invert(self, r):
        a, rg = self._grid()
        if np.any(np.diff(rg) <= 0):
            keep = np.concatenate([[True], np.diff(rg) > 0])
            a, rg = a[keep], rg[keep]
        # beyond the grid, continue with the end slopes
        out = np.interp(r, rg, a)
        lo_s = (a[1] - a[0]) / (rg[1] - rg[0])
        hi_s = (a[-1] - a[-2]) / (rg[-1] - rg[-2])
        out = np.where(r < rg[0], a[0] + (r - rg[0]) * lo_s, out)
        return np.where(r > rg[-1], a[-1] + (r - rg[-1]) * hi_s, out)

    def to_dict(self) -> dict:
        return {"kind": self.kind,
                "form": ("resistance_ohm = offset_ohm + slope_ohm_per_deg * angle_deg + pressure_k_ohm_per_psi * "
                         "(angle_deg / deg_per_psi) * radians(angle_deg) / cos((pi - radians(angle_deg)) / 2); "
                         "inverted numerically"),
                "slope_ohm_per_deg": self.slope_ohm_per_deg, "offset_ohm": self.offset_ohm,
                "pressure_k_ohm_per_psi": self.pressure_k_ohm_per_psi, "deg_per_psi": self.deg_per_psi,
                **self._ranges()}

    def table(self, n: int = 32):
        """A lookup table (resistance_ohm, angle_deg) over the valid range, for the firmware."""
        a = np.linspace(*self.angle_range_deg, n)
        return self.resistance_ohm(a), a


FACTORY = LinearMapping(FACTORY_SLOPE_OHM_PER_DEG, FACTORY_OFFSET_OHM, None, kind="factory")


def mapping_from_dict(d: dict) -> LinearMapping:
    kind = d.get("kind")
    common = dict(slope_ohm_per_deg=float(d["slope_ohm_per_deg"]), offset_ohm=float(d["offset_ohm"]),
                  angle_range_deg=None if d.get("angle_range_deg") is None
                  else tuple(float(v) for v in d["angle_range_deg"]))
    if kind in ("linear", "factory"):
        return LinearMapping(**common, kind=kind)
    if kind == "physical":
        return PhysicalMapping(**common, pressure_k_ohm_per_psi=float(d["pressure_k_ohm_per_psi"]),
                               deg_per_psi=float(d["deg_per_psi"]))
    raise ValueError(f"unknown mapping kind {kind!r}")
