"""Simulated flex sensor: from true bend angles to the glove's serial stream.

The static response is the physical model of DESIGN.md, a linear bending term plus the
knuckle-pressure term ``k * p(theta) * theta / cos((pi - theta)/2)``. The defaults are
chosen so that a straight line fitted to the static response at 0, 10, ..., 90 degrees
is exactly the reference's eq 17, R = 587.1 theta + 34 400 ohm, with the pressure term
carrying half of the mean error of the factory mapping over that range. On top come
exponential settling after every change (viscoelastic lag), optional hysteresis and
drift, resistance noise, and the ADC: oversampled, quantised conversions through the
voltage divider, then the firmware's own resistance and factory angle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from flexcal import __version__
from flexcal.calibration import reference
from flexcal.calibration.models import pressure_resistance_ohm, pressure_shape
from flexcal.capture.protocol import EOL, HEADER, format_comment, format_sample
from flexcal.divider import Divider, factory_angle_deg

_GRID = np.arange(0.0, 91.0, 10.0)


def _default_pressure_k() -> float:
    err = np.polyval(reference.EQ17, _GRID) - np.polyval(reference.EQ16, _GRID)
    return float(0.5 * err.mean() / pressure_shape(_GRID).mean())


def _default_linear(k: float) -> tuple[float, float]:
    # eq 17 minus the least-squares line through the pressure term on the grid:
    # then the total's least-squares line on the grid is eq 17 exactly.
    slope_p, offset_p = np.polyfit(_GRID, pressure_resistance_ohm(_GRID, k), 1)
    return reference.EQ17[0] - float(slope_p), reference.EQ17[1] - float(offset_p)


DEFAULT_PRESSURE_K = _default_pressure_k()
DEFAULT_SLOPE, DEFAULT_OFFSET = _default_linear(DEFAULT_PRESSURE_K)


@dataclass(frozen=True)
class SensorModel:
    """The sensor's response. Resistances in ohm, angles in degrees, times in seconds.

    ``resistance_ohm(theta) = offset_ohm + slope_ohm_per_deg * theta
    + pressure_k_ohm_per_psi * p(theta) * theta / cos((pi - theta)/2)``.
    """

    slope_ohm_per_deg: float = DEFAULT_SLOPE
    offset_ohm: float = DEFAULT_OFFSET
    pressure_k_ohm_per_psi: float = DEFAULT_PRESSURE_K
    noise_ohm: float = 40.0           # white noise on each reported sample
    adc_noise_lsb: float = 0.5        # noise of each conversion (dithers the quantisation)
    tau_s: float = 0.35               # settling time constant after a change
    hysteresis_ohm: float = 0.0       # + half when last moving up, - half when down
    drift_ohm_per_s: float = 0.0

    def __post_init__(self):
        for name in ("noise_ohm", "adc_noise_lsb", "tau_s", "hysteresis_ohm"):
            v = getattr(self, name)
            if not np.isfinite(v) or v < 0:
                raise ValueError(f"{name} must be a non-negative number, got {v!r}")

    def resistance_ohm(self, angle_deg):
        """Static (settled, noise-free) resistance at a bend angle."""
        a = np.asarray(angle_deg, float)
        return (self.offset_ohm + self.slope_ohm_per_deg * a
                + pressure_resistance_ohm(a, self.pressure_k_ohm_per_psi))


def simulate_readings(t_s, angle_deg, *, model: SensorModel = SensorModel(), divider: Divider = Divider(),
                      oversample: int = 16, rng=None) -> pd.DataFrame:
    """What the firmware reports for a time series of true angles.

    Parameters
    ----------
    t_s : (N,) array
        Sample times in seconds, increasing.
    angle_deg : (N,) array
        True bend angle at each sample time.
    model, divider : the sensor and the voltage divider.
    oversample : int
        ADC conversions averaged per reported sample.
    rng : numpy.random.Generator or int or None (seed 0).

    Returns
    -------
    DataFrame with columns ``t_s, angle_true_deg, resistance_true_ohm`` (settled,
    noise-free truth at that instant, lag included), ``adc`` (mean of the conversions),
    ``resistance_ohm`` (from the ADC through the divider) and ``angle_deg`` (the
    factory mapping).
    """
    rng = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(0 if rng is None else rng)
    t = np.asarray(t_s, float)
    a = np.asarray(angle_deg, float)
    if t.shape != a.shape or t.ndim != 1:
        raise ValueError(f"t_s and angle_deg must be 1-D arrays of one length, got {t.shape} and {a.shape}")
    if len(t) > 1 and np.any(np.diff(t) <= 0):
        raise ValueError("t_s must increase strictly")
    if int(oversample) < 1:
        raise ValueError(f"oversample must be a positive count of conversions, got {oversample!r}")
    r_eq = model.resistance_ohm(a)
    r = np.empty_like(r_eq)
    direction = np.sign(np.diff(a, prepend=a[0]))
    last = 1.0
    for i in range(len(t)):
        if direction[i] != 0:
            last = direction[i]
        target = r_eq[i] + 0.5 * model.hysteresis_ohm * last
        if i == 0 or model.tau_s == 0:
            r[i] = target
        else:
            r[i] = r[i - 1] + (1 - np.exp(-(t[i] - t[i - 1]) / model.tau_s)) * (target - r[i - 1])
    r_true = r + model.drift_ohm_per_s * (t - t[0])
    r_noisy = r_true + rng.normal(0, model.noise_ohm, len(t)) if model.noise_ohm else r_true
    ideal = divider.adc_from_resistance(r_noisy)
    conv = divider.quantise(ideal[:, None] + rng.normal(0, model.adc_noise_lsb, (len(t), int(oversample))))
    adc = conv.mean(axis=1)
    res = divider.resistance_from_adc(adc)
    return pd.DataFrame({
        "t_s": t, "angle_true_deg": a, "resistance_true_ohm": r_true,
        "adc": adc, "resistance_ohm": res, "angle_deg": factory_angle_deg(res),
    })


@dataclass(frozen=True)
class DeviceClock:
    """The Arduino's millis() relative to the host: boot offset and crystal drift."""

    boot_ms: int = 2_000
    drift_ppm: float = 0.0

    def t_ms(self, t_s):
        return (self.boot_ms + np.asarray(t_s, float) * 1000.0 * (1 + self.drift_ppm * 1e-6)).astype(np.int64)


def banner_lines(divider: Divider = Divider(), *, rate_hz: float = 50.0, version: str | None = None) -> list[str]:
    """The boot banner of the firmware (comment lines), as the simulator emits it."""
    return [
        format_comment(f"flexcal-firmware {version or __version__} (simulated by flexcal.synthetic)"),
        format_comment(divider.banner()),
        format_comment(f"mapping: factory angle_deg=(resistance_ohm-{reference.EQ16[1]:g})/{reference.EQ16[0]:g}"),
        format_comment(f"rate_hz={rate_hz:g}"),
    ]


def device_lines(readings: pd.DataFrame, *, clock: DeviceClock = DeviceClock(), divider: Divider = Divider(),
                 rate_hz: float = 50.0, banner: bool = True):
    """The lines the glove sends for ``readings`` (from ``simulate_readings``), without line ends."""
    if banner:
        yield from banner_lines(divider, rate_hz=rate_hz)
        yield HEADER
    t_ms = clock.t_ms(readings["t_s"].to_numpy())
    for tm, adc, r, ang in zip(t_ms, readings["adc"], readings["resistance_ohm"], readings["angle_deg"]):
        yield format_sample(int(tm), adc, r, ang)


def write_device_stream(path, readings: pd.DataFrame, **kwargs) -> None:
    """Write the device stream to a file, ``\\r\\n`` line ends as on the wire."""
    with open(path, "w", newline="") as f:
        for line in device_lines(readings, **kwargs):
            f.write(line + EOL)
