"""Fitting the calibration from the pairs table (and the pressure experiment).

``fit_calibration(pairs, pressure=None)`` decides which pairs to use (and says why the
others are excluded), fits eqs 16-19 of the reference, the physical models, the
corrections, and validates them leave-one-trial-out. Angles in degrees, resistances in
ohm, pressures in psi.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy import stats

from flexcal.calibration import reference
from flexcal.calibration.mapping import FACTORY, LinearMapping, PhysicalMapping
from flexcal.calibration.models import pressure_from_mass, pressure_shape
from flexcal.calibration.pairing import text_values
from flexcal.calibration.regression import LinearFit, ols, york
from flexcal.errors import FlexcalError

#: an answered photo whose angle sits this far (deg) off the robust line of the others is excluded
OUTLIER_MIN_DEG = 3.0
OUTLIER_MADS = 5.0
#: a correction is valid over the photographed angles widened by this much
VALID_MARGIN_DEG = 2.0
VALID_MARGIN_SHARE = 0.05
#: uncertainty assumed for a photo angle that comes without one (deg)
DEFAULT_ANGLE_UNC_DEG = 1.0


@dataclass
class PressureResult:
    table: pd.DataFrame             # mass_g, trial, angle_deg, resistance_ohm, pressure_psi, pressure_kpa
    angle_fit: LinearFit            # angle_deg vs pressure_psi
    resistance_fit: LinearFit       # resistance_ohm vs pressure_psi
    ratio_ohm_per_deg: float        # eq 19
    ratio_se: float
    contact_area_in2: float


@dataclass
class CalibrationResult:
    pairs: pd.DataFrame                           # all pairs, with step, used, excluded
    eq16: LinearFit                               # R vs firmware angle
    eq17: LinearFit                               # R vs photo angle, errors in both (ODR)
    eq17_ols: LinearFit
    eq18: dict                                    # error line = eq17 - eq16, with standard errors
    eq18_direct: LinearFit                        # per-pair error R - eq16(angle_actual) vs angle_actual
    steps: pd.DataFrame                           # per-step mean and std across trials
    reference_model: dict                         # eq 20 in the reference's form: k fitted on E_measured
    physical_fit: dict                            # R = R0 + b theta + k shape(theta), all three fitted
    mappings: dict                                # name -> mapping
    validation: pd.DataFrame                      # per mapping: rmse, bias, max, n, how
    validation_errors: pd.DataFrame               # per pair and mapping: angle error
    pressure: PressureResult | None = None
    notes: list = field(default_factory=list)

    @property
    def used(self) -> pd.DataFrame:
        return self.pairs[self.pairs["used"]]


def select_pairs(pairs: pd.DataFrame) -> pd.DataFrame:
    """A copy of ``pairs`` with ``used`` (bool) and ``excluded`` (the reason, '' when used)."""
    p = pairs.copy()
    reason = pd.Series("", index=p.index, dtype=object)

    def mark(mask, text):
        nonlocal reason
        m = mask & (reason == "")
        reason = reason.where(~m, text if isinstance(text, str) else text[m])

    why = pd.Series(text_values(p["reason"]), index=p.index, dtype=object)
    if "pairing_error" in p:
        err = pd.Series(text_values(p["pairing_error"]), index=p.index, dtype=object)
        mark(err != "", "trial not paired: " + err)
    angle_nan = ~np.isfinite(p["angle_actual_deg"].astype(float))
    mark(angle_nan, "no photo angle: " + why.replace("", "not measured"))
    mark(~np.isfinite(p["resistance_ohm"].astype(float)), "no serial samples at the photo's time")
    mark(p["status"].astype(str) == "low_confidence",
         "photo angle has low confidence: " + why)
    mark(~p["steady"].astype(bool), "signal not steady around the photo")
    ok = reason == ""
    if ok.sum() >= 4:
        x = p.loc[ok, "angle_actual_deg"].to_numpy(float)
        y = p.loc[ok, "resistance_ohm"].to_numpy(float)
        slope, icpt, _, _ = stats.theilslopes(y, x)
        if slope > 0:
            off_deg = (y - icpt) / slope - x   # how far the photo angle is from what the reading says
            mad = 1.4826 * np.median(np.abs(off_deg - np.median(off_deg)))
            limit = max(OUTLIER_MIN_DEG, OUTLIER_MADS * mad)
            bad = np.abs(off_deg - np.median(off_deg)) > limit
            texts = [f"photo angle {d:+.1f} deg off the line through the other photos (limit {limit:.1f}); "
                     "check its overlay" for d in -off_deg]
            idx = p.index[ok][bad]
            for i, j in zip(idx, np.flatnonzero(bad)):
                reason[i] = texts[j]
    p["excluded"] = reason
    p["used"] = reason == ""
    return p


def _step_stats(used: pd.DataFrame) -> pd.DataFrame:
    g = used.assign(error_ohm=used["resistance_ohm"] - np.polyval(reference.EQ16, used["angle_actual_deg"]),
                    angle_error_deg=used["angle_measured_deg"] - used["angle_actual_deg"]).groupby("step")
    out = g.agg(n=("trial", "count"),
                angle_actual_mean_deg=("angle_actual_deg", "mean"), angle_actual_std_deg=("angle_actual_deg", "std"),
                angle_measured_mean_deg=("angle_measured_deg", "mean"),
                angle_measured_std_deg=("angle_measured_deg", "std"),
                resistance_mean_ohm=("resistance_ohm", "mean"), resistance_std_ohm=("resistance_ohm", "std"),
                angle_error_mean_deg=("angle_error_deg", "mean"), angle_error_std_deg=("angle_error_deg", "std"))
    return out.reset_index()


def _fit_physical(angle, resistance, deg_per_psi) -> dict:
    """R = R0 + b theta + k shape(theta) by linear least squares, with covariance."""
    shape = pressure_shape(angle, deg_per_psi)
    a = np.column_stack([np.ones_like(angle), angle, shape])
    coef, *_ = np.linalg.lstsq(a, resistance, rcond=None)
    res = resistance - a @ coef
    dof = max(1, len(angle) - 3)
    cov = float(res @ res) / dof * np.linalg.inv(a.T @ a)
    se = np.sqrt(np.diag(cov))
    return {"form": "resistance_ohm = offset_ohm + slope_ohm_per_deg * angle_deg + pressure_k_ohm_per_psi * "
                    "p(angle) * radians(angle) / cos((pi - radians(angle)) / 2), p(angle) = angle_deg / deg_per_psi",
            "offset_ohm": float(coef[0]), "slope_ohm_per_deg": float(coef[1]), "pressure_k_ohm_per_psi": float(coef[2]),
            "offset_se": float(se[0]), "slope_se": float(se[1]), "pressure_k_se": float(se[2]),
            "covariance": cov.tolist(), "deg_per_psi": float(deg_per_psi),
            "rmse_ohm": float(np.sqrt(np.mean(res ** 2))), "n": int(len(angle))}


def _fit_reference_model(angle, resistance, eq16: LinearFit, deg_per_psi) -> dict:
    """Eq 20 in the reference's form: R_total = R_bending + R_pressure with R_bending the eq 16 line,
    k by least squares on E_measured = R_actual - R_bending; eqs 21-22 compare E_model with E_measured."""
    shape = pressure_shape(angle, deg_per_psi)
    e_measured = resistance - eq16(angle)
    k = float(shape @ e_measured / (shape @ shape))
    e_model = e_measured - k * shape
    dof = max(1, len(angle) - 1)
    k_se = float(np.sqrt((e_model @ e_model) / dof / (shape @ shape)))
    removed = 1.0 - np.mean(np.abs(e_model)) / np.mean(np.abs(e_measured))
    return {"form": "R_total = (slope_16 * angle_deg + offset_16) + k * p(angle) * radians(angle) / "
                    "cos((pi - radians(angle)) / 2); k by least squares on E_measured",
            "pressure_k_ohm_per_psi": k, "pressure_k_se": k_se, "deg_per_psi": float(deg_per_psi),
            "e_measured_ohm": e_measured.tolist(), "e_model_ohm": e_model.tolist(), "angle_deg": angle.tolist(),
            "mean_abs_e_measured_ohm": float(np.mean(np.abs(e_measured))),
            "mean_abs_e_model_ohm": float(np.mean(np.abs(e_model))), "share_of_error_removed": float(removed)}


def _eq17(used: pd.DataFrame) -> LinearFit:
    """Resistance against photo angle, errors in both: the photos' angle uncertainty, the
    readings' spread over the square root of their count (ODR, with the scatter fitted)."""
    angle, resistance = used["angle_actual_deg"].to_numpy(float), used["resistance_ohm"].to_numpy(float)
    angle_unc = used["angle_actual_unc_deg"].to_numpy(float)
    res_std, n = used["resistance_std_ohm"].to_numpy(float), used["n_samples"].to_numpy(float)
    sx = np.where(np.isfinite(angle_unc) & (angle_unc > 0), angle_unc, DEFAULT_ANGLE_UNC_DEG)
    sy = np.where(np.isfinite(res_std) & (n > 1), res_std / np.sqrt(np.maximum(n, 1)), 1.0)
    return york(angle, resistance, np.maximum(sx, 0.05), np.maximum(sy, 1.0), scatter=True)


def valid_range(angle_deg) -> tuple[float, float]:
    """Where a correction is trusted: the photographed angles, widened by max(2 deg, 5 % of the
    span) each side so that a straight finger's noise does not fall outside."""
    lo, hi = float(np.min(angle_deg)), float(np.max(angle_deg))
    m = max(VALID_MARGIN_DEG, VALID_MARGIN_SHARE * (hi - lo))
    return (lo - m, hi + m)


def _mappings(e17: LinearFit, phys: dict, angle_deg, deg_per_psi: float):
    """The two corrections from the fits of eq 17 and of the physical model, valid around ``angle_deg``."""
    rng = valid_range(angle_deg)
    return {"empirical": LinearMapping(e17.slope, e17.intercept, rng),
            "physical": PhysicalMapping(phys["slope_ohm_per_deg"], phys["offset_ohm"], rng,
                                        pressure_k_ohm_per_psi=phys["pressure_k_ohm_per_psi"],
                                        deg_per_psi=deg_per_psi)}


def validate(used: pd.DataFrame, deg_per_psi: float, notes: list):
    """Leave-one-trial-out angle errors of the factory mapping and the two corrections."""
    trials = sorted(used["trial"].unique())
    rows = []
    factory_err = used["angle_measured_deg"].to_numpy(float) - used["angle_actual_deg"].to_numpy(float)
    for (_, p), e in zip(used.iterrows(), factory_err):
        rows.append(dict(trial=p.trial, image=p.image, mapping="factory", error_deg=e))
    how = "leave-one-trial-out"
    if len(trials) < 2:
        how = "in-sample (one trial: cannot cross-validate)"
        notes.append("only one trial: the corrections are validated on the data they were fitted to, which "
                     "flatters them; record two or more trials to cross-validate")
        folds = [(used, used)]
    else:
        folds = [(used[used["trial"] != t], used[used["trial"] == t]) for t in trials]
    for train, test in folds:
        if len(train) < 4 or train["angle_actual_deg"].nunique() < 3:
            notes.append(f"trial {test['trial'].iloc[0]}: too few pairs left to fit without it; not validated")
            continue
        maps = _mappings(_eq17(train), _fit_physical(train["angle_actual_deg"].to_numpy(float),
                                                     train["resistance_ohm"].to_numpy(float), deg_per_psi),
                         train["angle_actual_deg"], deg_per_psi)
        for name, m in maps.items():
            pred = m.angle_deg(test["resistance_ohm"].to_numpy(float), extrapolate=True)
            for (_, p), e in zip(test.iterrows(), pred - test["angle_actual_deg"].to_numpy(float)):
                rows.append(dict(trial=p.trial, image=p.image, mapping=name, error_deg=e))
    errors = pd.DataFrame(rows, columns=["trial", "image", "mapping", "error_deg"])
    summary = errors.groupby("mapping", sort=False)["error_deg"].agg(
        rmse_deg=lambda e: float(np.sqrt(np.mean(e ** 2))), bias_deg="mean",
        max_abs_deg=lambda e: float(np.max(np.abs(e))), n="count").reset_index()
    summary["validation"] = [("all pairs (no fit)" if m == "factory" else how) for m in summary["mapping"]]
    return summary, errors


def fit_pressure(table: pd.DataFrame, contact_area_in2: float = reference.CONTACT_AREA_IN2,
                 source: str = "pressure table") -> PressureResult:
    """The pressure experiment: pressure from mass and contact area, angle and resistance against it, eq 19."""
    missing = {"mass_g", "angle_deg", "resistance_ohm"} - set(table.columns)
    if missing:
        raise FlexcalError(f"{source}: missing column(s) {', '.join(sorted(missing))}; the pressure table needs "
                           "mass_g,trial,angle_deg,resistance_ohm")
    t = table.copy()
    for c in ("mass_g", "angle_deg", "resistance_ohm"):
        t[c] = pd.to_numeric(t[c], errors="coerce")
    bad = t[["mass_g", "angle_deg", "resistance_ohm"]].isna().any(axis=1)
    if bad.any():
        raise FlexcalError(f"{source}, line {int(np.flatnonzero(bad.to_numpy())[0]) + 2}: not a number; "
                           "fix or delete that row")
    if t["mass_g"].nunique() < 2 or len(t) < 3:
        raise FlexcalError(f"{source}: needs at least 3 rows at 2 or more masses to fit a line")
    t["pressure_psi"], t["pressure_kpa"] = pressure_from_mass(t["mass_g"].to_numpy(), contact_area_in2)
    fa = ols(t["pressure_psi"], t["angle_deg"])
    fr = ols(t["pressure_psi"], t["resistance_ohm"])
    ratio = fr.slope / fa.slope
    ratio_se = abs(ratio) * np.hypot(fr.slope_se / fr.slope, fa.slope_se / fa.slope)
    return PressureResult(t, fa, fr, float(ratio), float(ratio_se), float(contact_area_in2))


def fit_calibration(pairs: pd.DataFrame, *, pressure: PressureResult | None = None) -> CalibrationResult:
    """Fit every model from the pairs table (DESIGN.md columns, plus ``step``)."""
    p = select_pairs(pairs)
    if "step" not in p:
        p["step"] = p.groupby("trial").cumcount() + 1
    used = p[p["used"]]
    notes: list[str] = []
    if len(used) < 4 or used["angle_actual_deg"].nunique() < 3:
        why = "; ".join(f"{n} x {r}" for r, n in p.loc[~p["used"], "excluded"].str.split(":").str[0]
                        .value_counts().items())
        raise FlexcalError(f"only {len(used)} usable pair(s) of {len(p)} (excluded: {why or 'none'}); a calibration "
                           "needs at least 4 photos at 3 or more angles")
    a = used["angle_actual_deg"].to_numpy(float)
    r = used["resistance_ohm"].to_numpy(float)
    am = used["angle_measured_deg"].to_numpy(float)
    eq16 = ols(am, r)
    eq17 = _eq17(used)
    eq17_ols = ols(a, r)
    eq18 = {"form": "R_err = slope * angle_deg + intercept (eq 17 - eq 16)",
            "slope": eq17.slope - eq16.slope, "intercept": eq17.intercept - eq16.intercept,
            "slope_se": float(np.hypot(eq17.slope_se, eq16.slope_se)),
            "intercept_se": float(np.hypot(eq17.intercept_se, eq16.intercept_se))}
    eq18_direct = ols(a, r - eq16(a))
    deg_per_psi = pressure.angle_fit.slope if pressure is not None else reference.ANGLE_VS_PRESSURE[0]
    if pressure is None:
        notes.append(f"no pressure experiment: p(angle) = angle / {deg_per_psi} psi/deg from the reference")
    validation, errors = validate(used, deg_per_psi, notes)
    physical = _fit_physical(a, r, deg_per_psi)
    return CalibrationResult(
        pairs=p, eq16=eq16, eq17=eq17, eq17_ols=eq17_ols, eq18=eq18, eq18_direct=eq18_direct,
        steps=_step_stats(used), reference_model=_fit_reference_model(a, r, eq16, deg_per_psi),
        physical_fit=physical, mappings={"factory": FACTORY, **_mappings(eq17, physical, a, deg_per_psi)},
        validation=validation, validation_errors=errors, pressure=pressure, notes=notes)
